// SPDX-License-Identifier: MIT
// ggrt serve: the views linked. Hovering a tree node (or stepping to it
// with j / k) draws its segment thick in the 3D view and outlines its
// object in the image; a click on a segment in the 3D view selects its
// node in the tree. The object's pixels come from the server's own find
// (no route gives an object-id image): a job per object, `some(kind ==
// eye && object == N)` with depth 1 and one sample (the pixels whose eye
// ray hits N first); for an object no eye ray reaches (inside glass,
// behind a mirror), `some(kind != shadow && object == N)` with the page's
// options at one sample (the pixels whose trees hit it). Kept once loaded,
// by object and the page's options (the second depends on them).
'use strict';
(function () {
  const $ = (id) => document.getElementById(id);
  const masks = {}; // object|options -> { mask: Uint8Array (W*H), how } or a pending Promise
  let selected = null; // { side, id }
  let hoverObj = -1;

  function nodes(side) {
    return Array.from(document.querySelectorAll('#tree-' + (side || 'a') + ' details.node'));
  }
  function nodeEl(side, id) {
    return document.querySelector('#tree-' + side + ' details.node[data-id="' + id + '"]');
  }

  // The node's object, from the tree JSON (absent fields: -1).
  function objectOf(side, id) {
    const t = window.ggrt && window.ggrt.traces, tr = t && t[side];
    if (!tr) return -1;
    const find = (n) => n.id === id ? n : n.children.map(find).find((x) => x) || null;
    for (const r of tr.json.roots) {
      const n = find(r);
      if (n) return n.hit && n.hit.object !== undefined ? n.hit.object : -1;
    }
    return -1;
  }

  // ---- the object in the image ----
  // Asked again until done while wanted() (the mouse still on that
  // object); one no longer wanted is cancelled, so that outlines the
  // mouse passed over do not queue ahead of the user's own finds.
  async function findMask(params, wanted) {
    const app = window.ggrt;
    let r;
    for (let i = 0; i < 3000; i++) {
      r = await app.api('/api/find', params);
      if (r.status === 200) break;
      if (!wanted()) {
        if (r.body && r.body.job) app.cancelJob(r.body.job.id);
        throw new Error('no longer wanted');
      }
      await new Promise((res) => setTimeout(res, 100));
    }
    if (!r.body.matched) return null;
    const m = await app.api('/api/find', Object.assign({ format: 'mask' }, params), 'buf');
    return new Uint8Array(m.body);
  }

  const maskKey = (obj) => obj + '|' + window.ggrt.state.a;
  async function loadMask(obj) {
    const key = maskKey(obj), a = window.ggrt.state.a;
    if (masks[key]) return masks[key];
    const p = (async () => {
      const eye = { where: 'some(kind == eye && object == ' + obj + ')', opts: 'depth=1 samples=1', limit: '0' };
      const wanted = () => hoverObj === obj;
      let m = await findMask(eye, wanted), how = 'seen first';
      if (!m) {
        // One sample a pixel: an outline, not a measurement.
        m = await findMask({ where: 'some(kind != shadow && object == ' + obj + ')', limit: '0',
          opts: (a ? a + ' ' : '') + 'samples=1' }, wanted);
        how = 'seen through other surfaces';
      }
      masks[key] = { mask: m, how: how };
      return masks[key];
    })();
    masks[key] = p;
    try {
      return await p;
    } catch (e) {
      delete masks[key];
      throw e;
    }
  }

  // Outline the object's pixels (tinted inside) on #objmask.
  function paintMask(obj, found) {
    const mask = found && found.mask;
    const c = $('objmask'), app = window.ggrt;
    if (!c || !app) return;
    const W = app.W, H = app.H, img = $('image');
    c.width = W; c.height = H;
    c.style.width = img.style.width; c.style.height = img.style.height;
    const g = c.getContext('2d');
    g.clearRect(0, 0, W, H);
    c.dataset.object = String(obj);
    c.dataset.how = found && found.how ? found.how : '';
    if (obj < 0 || !mask) { c.dataset.pixels = '0'; return; }
    const id = g.createImageData(W, H);
    let n = 0;
    for (let y = 0; y < H; y++) {
      for (let x = 0; x < W; x++) {
        const i = y * W + x;
        if (!mask[i]) continue;
        n++;
        const edge = x === 0 || y === 0 || x === W - 1 || y === H - 1 || !mask[i - 1] || !mask[i + 1] ||
          !mask[i - W] || !mask[i + W];
        const k = 4 * i;
        id.data[k] = 0; id.data[k + 1] = edge ? 230 : 200; id.data[k + 2] = edge ? 255 : 230;
        id.data[k + 3] = edge ? 255 : 90;
      }
    }
    g.putImageData(id, 0, 0);
    c.dataset.pixels = String(n);
  }

  async function showObject(obj) {
    hoverObj = obj;
    if (obj < 0) { paintMask(-1, null); return; }
    paintMask(-1, null);
    const key = maskKey(obj);
    try {
      const m = await loadMask(obj);
      // Not if the options changed meanwhile: the mask was theirs.
      if (hoverObj === obj && maskKey(obj) === key) {
        paintMask(obj, m);
        const h = $('hover');
        h.textContent = h.textContent.replace(/object #\d+: finding its pixels/, objectNote(obj));
      }
    } catch (e) {
      if (hoverObj === obj) $('hover').textContent = 'object ' + obj + ': ' + e.message;
    }
  }

  // ---- the node in focus: hover, keyboard or a click in the 3D view ----
  function focusNode(side, id, from) {
    const v = window.ggrtView3d;
    for (const e of document.querySelectorAll('.tree details.node.linked')) e.classList.remove('linked');
    if (id === null || id < 0) {
      if (v && v.highlight) v.highlight(-1);
      showObject(-1);
      return;
    }
    const e = nodeEl(side, id);
    if (e) e.classList.add('linked');
    if (v && v.highlight) v.highlight(side === 'a' ? id : -1);
    const obj = objectOf(side, id);
    showObject(obj);
    readout(side, id, obj, from);
  }

  function objectNote(obj) {
    const c = $('objmask');
    if (c.dataset.object !== String(obj)) return 'object #' + obj + ': finding its pixels';
    return c.dataset.pixels > 0 ? 'object #' + obj + ' outlined in the image (' + c.dataset.pixels +
      ' pixels, ' + c.dataset.how + ')' : 'object #' + obj + ' is in no pixel';
  }

  function readout(side, id, obj, from) {
    const app = window.ggrt, e = nodeEl(side, id);
    if (!e) return;
    const s = e.querySelector(':scope > summary');
    const text = s ? s.textContent.replace(/\s+/g, ' ').trim() : 'ray #' + id;
    $('hover').textContent = (app && app.state.px ? 'pixel ' + app.state.px.join(',') + '  ' : '') +
      (side === 'b' ? 'B ' : '') + text + (obj >= 0 ? '\n(' + from + ') ' + objectNote(obj) : '');
  }

  // Select a node: open the way to it, mark it, scroll to it.
  function selectNode(side, id, from) {
    const e = nodeEl(side, id);
    if (!e) return;
    for (let p = e; p && p.tagName === 'DETAILS'; p = p.parentElement) p.open = true;
    for (const x of document.querySelectorAll('.tree details.node.selected')) x.classList.remove('selected');
    e.classList.add('selected');
    selected = { side: side, id: id };
    document.body.dataset.selectedNode = side + ':' + id;
    const s = e.querySelector(':scope > summary');
    if (s) s.scrollIntoView({ block: 'nearest' });
    focusNode(side, id, from || 'selected');
  }

  // j / k: the next / previous node of the tree (in the order it reads).
  function step(d) {
    const side = selected ? selected.side : 'a', list = nodes(side);
    if (!list.length) return;
    let i = selected ? list.findIndex((e) => e.dataset.id === String(selected.id)) : -1;
    i = i < 0 ? (d > 0 ? 0 : list.length - 1) : Math.max(0, Math.min(list.length - 1, i + d));
    selectNode(side, parseInt(list[i].dataset.id, 10), 'keyboard');
  }

  function wire() {
    for (const side of ['a', 'b']) {
      const box = $('tree-' + side);
      box.addEventListener('mouseover', (ev) => {
        const s = ev.target.closest('details.node > summary');
        if (!s) return;
        focusNode(side, parseInt(s.parentElement.dataset.id, 10), 'hover');
      });
      box.addEventListener('mouseleave', () => {
        if (selected) focusNode(selected.side, selected.id, 'selected');
        else focusNode('a', -1);
      });
    }
    document.addEventListener('keydown', (e) => {
      const t = e.target.tagName;
      if (t === 'INPUT' || t === 'TEXTAREA' || e.ctrlKey || e.metaKey || e.altKey) return;
      if (t === 'SELECT' && /^Arrow/.test(e.key) && e.target.closest('.bar:not(#find-form)') &&
          !e.target.closest('.opts')) {
        // A dropdown of the image's bar does not take the arrows: they move
        // the pixel (the dropdown opens with the mouse, or Alt+Down).
        e.preventDefault();
        e.stopPropagation();
        e.target.blur();
        $('image').focus();
        $('image').dispatchEvent(new KeyboardEvent('keydown', { key: e.key, shiftKey: e.shiftKey, bubbles: true }));
        return;
      }
      if (t === 'SELECT') return;
      if (e.key === 'j' || e.key === 'k') { e.preventDefault(); step(e.key === 'j' ? 1 : -1); }
      if (e.key === 'Escape') { selected = null; document.body.dataset.selectedNode = ''; focusNode('a', -1); }
    }, true);
    // The overlay and zoom dropdowns give the keyboard back once used.
    for (const id of ['overlay-select', 'zoom']) {
      $(id).addEventListener('change', () => { $(id).blur(); $('image').focus(); });
    }
    // The 3D view sits under the image and moves into the "rays 3D" tab
    // (larger) while that tab is shown.
    const tab = $('tab-rays3d'), home = $('home3d'), box = $('box3d');
    new MutationObserver(() => {
      const target = tab.hidden ? home : tab;
      if (box.parentElement !== target) {
        target.appendChild(box);
        box.classList.toggle('big', !tab.hidden);
        if (window.ggrtView3d) window.ggrtView3d.draw();
      }
    }).observe(tab, { attributes: true, attributeFilter: ['hidden'] });
    if (!tab.hidden) { tab.appendChild(box); box.classList.add('big'); }
  }

  document.addEventListener('ggrt:ready', wire);
  document.addEventListener('ggrt:pixel', () => {
    selected = null;
    document.body.dataset.selectedNode = '';
    hoverObj = -1;
    paintMask(-1, null);
  });
  document.addEventListener('ggrt:image', () => {
    const c = $('objmask'), img = $('image');
    if (c) { c.style.width = img.style.width; c.style.height = img.style.height; }
  });
  window.ggrtLinks = { selectNode: selectNode, focusNode: focusNode, step: step };
})();
