// SPDX-License-Identifier: MIT
// ggrt serve: what is on screen, out of the page. The tree as JSON (the
// bytes of `ggrt trace --format json`), the rays as SVG (`ggrt trace
// --svg`'s views) and as OBJ line geometry, the image and the overlay or
// mask shown as PNG, and the `ggrt trace` / `ggrt find` command lines that
// print the same.
'use strict';
(function () {
  const $ = (id) => document.getElementById(id);

  function save(blob, name) {
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = name;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
    $('export-note').textContent = 'saved ' + name;
  }

  function sideParams(side) {
    const s = window.ggrt.state, t = side === 'b' ? s.b : s.a;
    return t ? { opts: t } : {};
  }
  function pixelParams() {
    const app = window.ggrt, p = Object.assign({ x: app.state.px[0], y: app.state.px[1] }, sideParams('a'));
    const t = app.traces && app.traces.a;
    if (t && t.json.sample !== null && t.json.sample !== undefined) p.sample = t.json.sample;
    return p;
  }
  const tag = () => window.ggrt.state.px.join('-');

  // ---- the command line: the server's options with the page's over them ----
  function words(text) {
    const o = {};
    for (const w of (text || '').split(/[\s,]+/)) {
      if (!w) continue;
      const i = w.indexOf('=');
      o[i < 0 ? w : w.slice(0, i)] = i < 0 ? '' : w.slice(i + 1);
    }
    return o;
  }
  const quote = (s) => /^[A-Za-z0-9_./=,:+-]+$/.test(s) ? s : "'" + s.replace(/'/g, "'\\''") + "'";
  // A file name that starts with '-' would read as options: "./-x.nff" (as ggrt's own replay lines).
  const file = (s) => s.startsWith('-') ? './' + s : s;
  function flags(side) {
    const app = window.ggrt;
    const o = Object.assign(words(app.info.options), words(side === 'b' ? app.state.b : app.state.a));
    const out = [], acc = [];
    for (const [k, v] of Object.entries(o)) {
      if (k === 'size') out.push('-s', v);
      else if (k === 'depth') out.push('-d', v);
      else if (k === 'samples') out.push('-n', v);
      else if (k === 'threads') out.push('-j', v);
      else if (k === 'ray-budget') out.push('--ray-budget', v);
      else if (k === 'spd' || k === 'spd-rules' || k === 'corners' || k === 'force-effects') out.push('--' + k);
      else if (k !== 'crop') acc.push(k + '=' + v);
    }
    if (acc.length) out.push('-a', acc.join(','));
    return out;
  }
  function traceCommand() {
    const app = window.ggrt, s = app.state;
    const c = ['ggrt', 'trace', file(app.info.scene), '--pixel', s.px.join(',')];
    const t = app.traces && app.traces.a;
    if (t && t.json.sample !== null && t.json.sample !== undefined) c.push('--sample', String(t.json.sample));
    if (s.diff) {
      c.push('--diff', '--a', s.a || '', '--b', s.b || '');
      return c.concat(flags('server')).map(quote).join(' ');
    }
    if (s.path && t && t.json.sample === null) c.push('--path', s.path);
    return c.concat(flags('a')).map(quote).join(' ');
  }
  // The find of the overlay shown: the path's when it is shown or no predicate is set.
  function findCommand() {
    const app = window.ggrt, s = app.state;
    const path = s.path && (s.overlay === 'path' || !s.find);
    if (!s.find && !path) return '';
    return ['ggrt', 'find', file(app.info.scene)].concat(path ? ['--path', s.path] : ['--where', s.find])
      .concat(flags('a')).map(quote).join(' ');
  }

  function showCommands() {
    const app = window.ggrt;
    if (!app || !app.info) return;
    $('cmd-trace').value = app.state.px ? traceCommand() : '';
    $('cmd-find').value = findCommand();
    $('cmd-find').parentElement.hidden = !app.state.find && !app.state.path;
  }

  async function copy(id) {
    const box = $(id);
    box.select();
    try {
      await navigator.clipboard.writeText(box.value);
      $('export-note').textContent = 'copied';
    } catch (e) {
      // Without clipboard access the text stays selected: Ctrl+C copies it.
      $('export-note').textContent = 'selected: press Ctrl+C to copy';
    }
  }

  // ---- the rays as OBJ: one polyline a ray, a group per kind ----
  function rayObj() {
    const app = window.ggrt, j = app.traces.a.json, lo = app.info.bounds.lo, hi = app.info.bounds.hi;
    const reach = 1.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    const v = [], groups = {};
    const add = (g, a, b) => {
      v.push(a, b);
      (groups[g] = groups[g] || []).push(v.length - 1);
    };
    const walk = (n) => {
      const d = n.direction, l = Math.hypot(d[0], d[1], d[2]) || 1;
      add(n.kind, n.origin, n.hit ? n.hit.point : n.origin.map((x, i) => x + d[i] / l * reach));
      if (n.hit) {
        for (const L of n.hit.lights || []) {
          if (L.verdict === 'facing-away') continue;
          const t = L.verdict === 'blocked' && typeof L.t_block === 'number' ? L.t_block : 1;
          add('shadow_' + L.verdict, L.origin, L.origin.map((x, i) => x + L.direction[i] * t));
        }
      }
      n.children.forEach(walk);
    };
    j.roots.forEach(walk);
    const out = ['# ggrt serve: the rays of pixel ' + j.pixel.join(',') + ' of ' + app.info.scene +
      ' (' + (j.options || app.state.a || 'the server\'s options') + ')', '# misses are drawn to ' + reach.toPrecision(4)];
    // Non-finite coordinates (null or "inf"/"nan" strings) are written as
    // nan, which OBJ readers reject loudly rather than misplace.
    for (const p of v) out.push('v ' + p.map((x) => typeof x === 'number' && isFinite(x) ? x.toPrecision(9) : 'nan').join(' '));
    for (const [g, ends] of Object.entries(groups)) {
      out.push('g ' + g);
      for (const e of ends) out.push('l ' + e + ' ' + (e + 1));
    }
    return out.join('\n') + '\n';
  }

  async function run(what) {
    const app = window.ggrt;
    if (!app.state.px && what !== 'image' && what !== 'overlay') {
      $('export-note').textContent = 'click a pixel first';
      return;
    }
    try {
      if (what === 'json') {
        const r = await app.api('/api/trace', pixelParams(), 'text');
        save(new Blob([r.body], { type: 'application/json' }), 'ggrt-trace-' + tag() + '.json');
      } else if (what === 'svg') {
        const r = await app.api('/api/trace', Object.assign({ format: 'svg' }, pixelParams()), 'blob');
        save(r.body, 'ggrt-rays-' + tag() + '.svg');
      } else if (what === 'obj') {
        save(new Blob([rayObj()], { type: 'model/obj' }), 'ggrt-rays-' + tag() + '.obj');
      } else if (what === 'image') {
        // Not a download that arrives unannounced when a render ends.
        if (!app.imageReady()) {
          $('export-note').textContent = 'the image is still rendering: save it when it is done';
          return;
        }
        const r = await app.api('/api/image', Object.assign({ format: 'png' }, sideParams('a')), 'blob');
        save(r.body, 'ggrt-image.png');
      } else if (what === 'overlay') {
        // An overlay that failed ('find-error', ...) has nothing drawn.
        const c = $('overlay'), m = $('objmask'), k = c.dataset.kind || 'none';
        const src = k !== 'none' && !/-error$/.test(k) ? c : m && m.dataset.pixels > 0 ? m : null;
        if (!src) { $('export-note').textContent = 'no overlay or mask on the image'; return; }
        const name = src === c ? 'ggrt-' + c.dataset.kind + '.png' : 'ggrt-object-' + m.dataset.object + '.png';
        src.toBlob((b) => save(b, name), 'image/png');
      }
    } catch (e) {
      $('export-note').textContent = e.message;
    }
  }

  document.addEventListener('ggrt:ready', () => {
    for (const b of document.querySelectorAll('#export [data-export]')) {
      b.addEventListener('click', () => run(b.dataset.export));
    }
    $('copy-trace').addEventListener('click', () => copy('cmd-trace'));
    $('copy-find').addEventListener('click', () => copy('cmd-find'));
    showCommands();
  });
  document.addEventListener('ggrt:pixel', showCommands);
  window.addEventListener('hashchange', showCommands);
  window.ggrtExport = { traceCommand: traceCommand, findCommand: findCommand, rayObj: rayObj, show: showCommands };
})();
