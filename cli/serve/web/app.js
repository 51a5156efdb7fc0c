// SPDX-License-Identifier: MIT
// ggrt serve: the page. Plain JavaScript, no libraries, nothing from the
// network but this server's JSON API (docs/serve.md), which every call
// reaches with the token in an Authorization header.
'use strict';
(function () {
  const TOKEN = new URLSearchParams(location.search).get('token') || '';
  const $ = (id) => document.getElementById(id);

  // ---- the render options a view can change: the settings of
  // ggRenderOptionsParse (the text of ggrt diff's --a/--b), applied over the
  // server's own options ----
  const OPTS = [
    ['depth', 'depth', 'int', 1, 16],
    ['samples', 'samples', 'int', 1, 64],
    ['ray-budget', 'ray budget (rays per eye ray)', 'text', '1024'],
    ['refract', 'refract', ['accurate', 'textbook', 'exact']],
    ['fresnel', 'fresnel', ['scene', 'none', 'schlick', 'exact']],
    ['sphere', 'sphere', ['stable', 'textbook']],
    ['offset', 'offset (scaled, fixed or eps)', 'text', 'scaled'],
    ['texture', 'texture', ['scene', 'bilinear', 'nearest']],
    ['wavelengths', 'wavelengths', ['rgb', 'one']],
    ['cutoff', 'cutoff (0 = off)', 'text', '0'],
    ['implicit-tol', 'implicit tol (own or T)', 'text', 'own'],
    ['gradient', 'gradient (exact or h)', 'text', 'exact'],
    ['intersect', 'intersect', ['double', 'float']],
    ['shadows', 'shadows', ['colored', 'opaque']],
    ['phong', 'phong power', ['exact', 'fast']],
    ['spd', 'SPD: rule, corners, depth 5', 'flag'],
    ['spd-rules', 'SPD rule only', 'flag'],
    ['corners', 'pixel corners', 'flag'],
    ['force-effects', 'force effects', 'flag'],
  ];
  const OVERLAYS = ['none', 'rays', 'depth', 'time', 'find', 'path', 'diff'];
  const TABS = ['tree', 'rays3d', 'views', 'ledger', 'diag', 'text'];
  const KIND_COLOR = { eye: '#111', reflect: '#1f5fd0', refract: '#17a34a', tir: '#c026d3' };

  const state = {
    a: '', b: '', // option text over the server's options (ggRenderOptionsParse)
    diff: false, px: null, overlay: 'none', opacity: 0.75, zoom: 0, tab: 'tree', find: '',
    path: '', pathDim: false, // a light-path expression: the tree filter and the share heatmap
  };
  let info = null, scene = null, W = 0, H = 0;
  const images = {}; // 'a' / 'b' -> { q, bmp, rgb }
  const overlays = {}; // key -> { bmp, values, max, legend }
  let traces = { key: '', a: null, b: null }; // JSON of the selected pixel
  let generation = 0; // a newer view (image, overlay) makes older answers stale
  let pixelGen = 0; // the same for the selected pixel

  // ---- small helpers ----

  // printf's %.<p>g, so that values read as ggrt prints them (%.9g).
  function fmtG(x, p) {
    if (x === null || x === undefined) return 'nan';
    if (!isFinite(x)) return isNaN(x) ? 'nan' : (x > 0 ? 'inf' : '-inf');
    if (x === 0) return (1 / x < 0) ? '-0' : '0';
    const e = parseInt(x.toExponential(p - 1).split('e')[1], 10);
    let s;
    if (e < -4 || e >= p) {
      let [m, ex] = x.toExponential(p - 1).split('e');
      if (m.indexOf('.') >= 0) m = m.replace(/0+$/, '').replace(/\.$/, '');
      const n = parseInt(ex, 10);
      s = m + 'e' + (n < 0 ? '-' : '+') + String(Math.abs(n)).padStart(2, '0');
    } else {
      s = x.toFixed(Math.max(0, p - 1 - e));
      if (s.indexOf('.') >= 0) s = s.replace(/0+$/, '').replace(/\.$/, '');
    }
    return s;
  }
  const g4 = (x) => fmtG(x, 4), g6 = (x) => fmtG(x, 6);
  const vec = (v) => '(' + v.map(g6).join(', ') + ')';
  const col = (c) => '(' + c.map(g4).join(' ') + ')';
  function srgb(c) {
    const f = (v) => {
      if (!(v > 0)) return 0;
      if (v >= 1) return 255;
      const s = v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055;
      return Math.round(s * 255);
    };
    return 'rgb(' + f(c[0]) + ',' + f(c[1]) + ',' + f(c[2]) + ')';
  }
  function el(tag, cls, text) {
    const e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    return e;
  }
  function swatch(c) {
    const s = el('span', 'sw');
    s.style.background = srgb(c);
    return s;
  }
  const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

  // The banner, and what it came from ('pixel': the selected pixel's
  // requests, 'view': the image and overlay, 'find': the find box), so
  // that a later success of the same kind clears the error it supersedes.
  function showError(msg, from) {
    const e = $('error');
    e.textContent = msg;
    e.hidden = !msg;
    e.dataset.from = msg ? from || '' : '';
  }
  function clearError(from) {
    if ($('error').dataset.from === from) showError('');
  }
  function status(text, frac) {
    $('status-text').textContent = text;
    $('status-text').title = text; // the whole line where it does not fit
    const p = $('progress');
    if (frac === undefined) p.classList.add('done');
    else { p.classList.remove('done'); p.value = frac; }
  }

  class ApiError extends Error {
    constructor(status, msg) { super(msg); this.status = status; }
  }

  // GET path?params; as: 'json' (default), 'blob', 'buf', 'text'. A 503
  // (every job slot busy) is waited out as its Retry-After says, with
  // "waiting" in the status line, for up to about 10 minutes. Binary
  // answers (blob, buf: images, masks, floats) must be 200: a 202 (the
  // job was replaced meanwhile and runs again) is its JSON progress, not
  // the data, and is asked again.
  async function api(path, params, as) {
    const q = new URLSearchParams(params || {}).toString();
    const binary = as === 'blob' || as === 'buf';
    let r;
    for (let tries = 0, running = 0; ; tries++) {
      try {
        r = await fetch(path + (q ? '?' + q : ''), {
          headers: { Authorization: 'Bearer ' + TOKEN }, cache: 'no-store',
        });
      } catch (e) {
        // fetch rejects only when no answer came: a network error.
        throw new ApiError(0, 'the server is not answering (stopped?): ' + path + ' failed (' + e.message + ')');
      }
      if (binary && r.status === 202 && running < 6000) {
        running++;
        tries--;
        await sleep(150);
        continue;
      }
      if (r.status !== 503 || tries >= 100) break;
      const wait = Math.min(30, Math.max(1, parseInt(r.headers.get('Retry-After'), 10) || 1));
      status('waiting: the server is busy, asking again in ' + wait + ' s');
      $('status').dataset.waiting = '1';
      await sleep(1000 * wait);
    }
    delete $('status').dataset.waiting;
    if (!r.ok || (binary && r.status !== 200)) {
      let msg = r.status + ' ' + r.statusText;
      try { msg = (await r.json()).error || msg; } catch (e) { /* not JSON */ }
      throw new ApiError(r.status, msg);
    }
    const body = as === 'blob' ? await r.blob() : as === 'buf' ? await r.arrayBuffer()
      : as === 'text' ? await r.text() : await r.json();
    return { status: r.status, body: body, headers: r.headers };
  }

  // ---- options ----

  function optParams(side) {
    const t = side === 'b' ? state.b : state.a;
    return t ? { opts: t } : {};
  }
  function diffParams() {
    const p = optParams('a');
    if (state.b) p.b = state.b;
    return p;
  }
  const keyOf = (p) => new URLSearchParams(p).toString();

  // "depth=3 refract=textbook spd" -> {depth: '3', refract: 'textbook', spd: '1'}
  function parseText(t) {
    const o = {};
    for (const w of (t || '').split(/[\s,]+/)) {
      if (!w) continue;
      const i = w.indexOf('=');
      if (i < 0) o[w] = '1';
      else o[w.slice(0, i)] = w.slice(i + 1);
    }
    if (o.spd) o.corners = o['spd-rules'] = '1'; // what spd sets, ticked
    return o;
  }
  let serverOpts = {};
  function serverValue(name) {
    const spec = OPTS.find((o) => o[0] === name);
    if (name in serverOpts) return serverOpts[name];
    if (spec[2] === 'flag') return '0';
    if (spec[2] === 'int') return '0';
    if (spec[2] === 'text') return spec[3];
    if (name === 'offset' && serverOpts.offset) return serverOpts.offset;
    return spec[2][0];
  }

  function buildPanel(side) {
    const box = $('opts-' + side);
    box.textContent = '';
    for (const [name, label, type, lo, hi] of OPTS) {
      const l = el('label', type === 'flag' ? 'flag' : '');
      let input;
      if (type === 'flag') {
        input = el('input');
        input.type = 'checkbox';
      } else if (Array.isArray(type)) {
        input = el('select');
        for (const c of type) input.appendChild(el('option', '', c)).value = c;
      } else if (type === 'int') {
        input = el('select');
        input.appendChild(el('option', '', 'scene')).value = '0';
        for (let i = lo; i <= hi; i++) {
          if (name === 'samples' && i > 2 && [4, 9, 16, 25, 36, 49, 64].indexOf(i) < 0) continue;
          input.appendChild(el('option', '', String(i))).value = String(i);
        }
      } else {
        input = el('input');
        input.type = 'text';
        input.size = 8;
      }
      input.dataset.opt = name;
      input.id = 'opt-' + side + '-' + name;
      const span = el('span', '', label);
      if (type === 'flag') { l.appendChild(input); l.appendChild(span); } else { l.appendChild(span); l.appendChild(input); }
      box.appendChild(l);
    }
    fillPanel(side);
  }

  function fillPanel(side) {
    const o = parseText(side === 'b' ? state.b : state.a);
    for (const input of $('opts-' + side).querySelectorAll('[data-opt]')) {
      const name = input.dataset.opt, v = name in o ? o[name] : serverValue(name);
      if (input.type === 'checkbox') {
        input.checked = v === '1';
        // A setting's text only adds: what the server has on stays on.
        input.disabled = serverValue(name) === '1';
      } else {
        input.value = v;
        if (input.tagName === 'SELECT' && input.value !== v) input.value = input.options[0].value;
      }
      input.parentNode.classList.toggle('changed', name in o && o[name] !== serverValue(name));
    }
  }

  // The panel as option text: the settings that differ from the server's,
  // after the words of the side's text that the panel has no field for.
  function readPanel(side) {
    const words = Object.entries(parseText(side === 'b' ? state.b : state.a))
      .filter(([k]) => !OPTS.some((o) => o[0] === k)).map(([k, v]) => v === '1' ? k : k + '=' + v);
    for (const input of $('opts-' + side).querySelectorAll('[data-opt]')) {
      const name = input.dataset.opt;
      const v = input.type === 'checkbox' ? (input.checked ? '1' : '0') : input.value.trim();
      if (v === serverValue(name) || v === '') continue;
      // '0' in a depth or samples list is "scene"; typed in a text field it
      // is a value, passed on so that the server says what it takes.
      if (input.type === 'checkbox') { if (v === '1') words.push(name); } else if (v !== '0' || input.tagName !== 'SELECT') words.push(name + '=' + v);
    }
    // spd says the rule and the corners itself
    return words.filter((w) => words.indexOf('spd') < 0 || (w !== 'spd-rules' && w !== 'corners')).join(' ');
  }

  // ---- URL state: #px=X,Y&ov=...&tab=...&zoom=...&find=...&path=...&pdim=1&a=OPTIONS&b=OPTIONS&diff=1 ----

  // Back and Forward: a step that changes what is looked at (another
  // pixel, tab or overlay, a find or path submitted, options rendered,
  // diff mode on or off) is a new history entry (push); an adjustment of
  // how it is shown (zoom, opacity, dimming, the 3D camera: view3d.js) and
  // the page's own writing of the address it loaded or was taken back to
  // replace the entry in place, so that history is not flooded and Back
  // undoes one step. An address equal to the one shown is never pushed.
  function writeHash(push) {
    const p = new URLSearchParams();
    if (state.px) p.set('px', state.px[0] + ',' + state.px[1]);
    if (state.overlay !== 'none') p.set('ov', state.overlay);
    if (state.tab !== 'tree') p.set('tab', state.tab);
    if (state.zoom) p.set('zoom', String(state.zoom));
    if (state.opacity !== 0.75) p.set('alpha', String(state.opacity));
    if (state.find) p.set('find', state.find);
    if (state.path) p.set('path', state.path);
    if (state.pathDim) p.set('pdim', '1');
    if (state.diff) p.set('diff', '1');
    if (state.a) p.set('a', state.a);
    if (state.b) p.set('b', state.b);
    const cam = new URLSearchParams(location.hash.slice(1)).get('cam');
    if (cam) p.set('cam', cam);
    const h = p.toString(), url = location.pathname + location.search + (h ? '#' + h : '');
    if (push && url !== location.pathname + location.search + location.hash) history.pushState(null, '', url);
    else history.replaceState(null, '', url);
  }

  function readHash() {
    const p = new URLSearchParams(location.hash.slice(1));
    state.a = p.get('a') || '';
    state.b = p.get('b') || '';
    const px = (p.get('px') || '').split(',').map((s) => parseInt(s, 10));
    state.px = px.length === 2 && px.every((v) => v >= 0) && px[0] < W && px[1] < H ? px : null;
    state.overlay = OVERLAYS.indexOf(p.get('ov')) >= 0 ? p.get('ov') : 'none';
    state.tab = TABS.indexOf(p.get('tab')) >= 0 ? p.get('tab') : 'tree';
    state.zoom = Math.min(ZOOM_MAX, Math.max(0, parseInt(p.get('zoom') || '0', 10) || 0));
    const a = parseFloat(p.get('alpha'));
    state.opacity = a >= 0 && a <= 1 ? a : 0.75;
    state.find = p.get('find') || '';
    state.path = p.get('path') || '';
    state.pathDim = p.get('pdim') === '1';
    state.diff = p.get('diff') === '1';
  }

  // ---- renders ----

  // The jobs this page is waiting for (id -> loops polling it): a job a
  // newer view no longer waits for is cancelled (/api/cancel), which the
  // server does only if no request for it comes within a second (another
  // view or page may share it); those left when the page goes away too.
  const polling = new Map();
  function cancelJob(id, keepalive) {
    if (!id || polling.get(id)) return;
    fetch('/api/cancel?id=' + id, {
      headers: { Authorization: 'Bearer ' + TOKEN }, cache: 'no-store', keepalive: !!keepalive,
    }).catch(() => { /* the server is gone: nothing to cancel */ });
  }
  function watch(id, on) {
    const n = (polling.get(id) || 0) + (on ? 1 : -1);
    if (n > 0) polling.set(id, n); else polling.delete(id);
  }
  // "label: running 40%", or what a queued job waits behind.
  function jobStatus(label, j) {
    const pc = (d, t) => Math.round(100 * d / Math.max(1, t)) + '%';
    let t = label + ': ' + j.state + ' ' + pc(j.done, j.total);
    if (j.state === 'queued' && j.running) {
      t = label + ': queued behind ' + j.running.what + ', ' + pc(j.running.done, j.running.total) + ' done' +
        (j.ahead > 1 ? ' (' + (j.ahead - 1) + ' more job' + (j.ahead > 2 ? 's' : '') + ' ahead)' : '');
    } else if (j.state === 'queued' && j.ahead > 0) {
      t = label + ': queued, ' + j.ahead + ' job' + (j.ahead > 1 ? 's' : '') + ' ahead';
    }
    status(t, j.done / Math.max(1, j.total));
  }
  // Poll path until its job is done (done(r) says so): r, or null when a
  // newer view made this one stale (the job is then cancelled unless
  // something else here still waits for it).
  async function pollJob(path, params, label, gen, done, pause) {
    let id = 0;
    try {
      for (;;) {
        const r = await api(path, params);
        const j = r.body && r.body.job;
        if (j && j.id !== id) { if (id) watch(id, false); id = j.id; watch(id, true); }
        if (gen !== generation && gen !== undefined) {
          watch(id, false);
          const was = id;
          id = 0;
          if (j && j.state !== 'done') cancelJob(was);
          return null;
        }
        if (done(r)) return r;
        if (j && j.state === 'failed') throw new ApiError(500, j.error);
        if (j) jobStatus(label, j);
        await sleep(pause);
      }
    } finally {
      if (id) watch(id, false);
    }
  }
  window.addEventListener('pagehide', () => { for (const id of Array.from(polling.keys())) { polling.delete(id); cancelJob(id, true); } });

  // Ask for a render until it is done, showing its progress.
  async function waitRender(params, kind, label, gen) {
    const p = Object.assign({}, params);
    if (kind !== 'image') p.kind = kind;
    return (await pollJob('/api/render', p, label, gen, (r) => r.body.job.state === 'done', 120)) !== null;
  }

  async function loadImage(side, gen) {
    const params = optParams(side), q = keyOf(params);
    // An image already here: its summary again (the line may say "error"
    // from the options that were refused before it).
    if (images[side] && images[side].q === q) {
      if (images[side].said) status(images[side].said);
      return images[side];
    }
    const t0 = performance.now();
    if (!(await waitRender(params, 'image', 'rendering ' + side.toUpperCase(), gen))) return null;
    const [png, f32] = await Promise.all([
      api('/api/image', Object.assign({ format: 'png' }, params), 'blob'),
      api('/api/image', Object.assign({ format: 'f32' }, params), 'buf')]);
    const bmp = await createImageBitmap(png.body);
    // An answer that comes after a newer view's must not replace its
    // image: the hover would read this one's values.
    if (gen !== generation) return null;
    images[side] = { q: q, bmp: bmp, rgb: new Float32Array(f32.body) };
    const r = await api('/api/render', params);
    if (gen !== generation) return null;
    const st = r.body.job.stats, rays = st.eye + st.reflect + st.refract + st.shadow;
    // The words of ggrt render's summary: how many shadow rays nothing of
    // the light got through, and how many arrived dimmed.
    $('viewport').dataset['rays' + side.toUpperCase()] =
      [rays, st.shadow, st.shadow_blocked, st.shadow_attenuated].join(' ');
    images[side].said = 'rendered ' + side.toUpperCase() + ' in ' + r.body.job.seconds.toFixed(2) + ' s' +
      ' (this page waited ' + ((performance.now() - t0) / 1000).toFixed(1) + ' s): ' +
      rays.toLocaleString() + ' rays, shadow ' + st.shadow.toLocaleString() + ' (blocked ' +
      st.shadow_blocked.toLocaleString() + ', attenuated ' + st.shadow_attenuated.toLocaleString() + ')';
    status(images[side].said);
    return images[side];
  }

  // Zoom: 0 fits the image to the window; else 1..ZOOM_MAX screen pixels
  // a pixel, the dropdown (fit, 1x..16x) always showing which.
  const ZOOM_MAX = 16;

  function sizeCanvases() {
    let z = state.zoom;
    if (!z) {
      // Fit the width left of the tree and half the height (the 3D view
      // goes under the image).
      const room = Math.max(200, Math.min(820, window.innerWidth * 0.55));
      const roomH = Math.max(150, (window.innerHeight - 120) / 2);
      z = Math.max(1, Math.floor(Math.min(room / W, roomH / H)));
    }
    for (const id of ['image', 'overlay']) {
      const c = $(id);
      if (c.width !== W) c.width = W;
      if (c.height !== H) c.height = H;
      c.style.width = (W * z) + 'px';
      c.style.height = (H * z) + 'px';
    }
    const m = $('marker');
    m.width = W * z; m.height = H * z;
    m.style.width = (W * z) + 'px'; m.style.height = (H * z) + 'px';
    $('zoom').value = String(state.zoom);
    return z;
  }

  // Whether image A of the options shown is here (a find waits for it).
  function imageReady() {
    return !!(images.a && images.a.q === keyOf(optParams('a')));
  }

  function drawImage() {
    const img = images.a;
    if (!img) return;
    sizeCanvases();
    $('image').getContext('2d').drawImage(img.bmp, 0, 0);
    $('viewport').dataset.image = img.q || 'default';
    drawMarker();
    document.dispatchEvent(new Event('ggrt:image'));
  }

  function drawMarker() {
    const m = $('marker'), g = m.getContext('2d'), z = m.width / W;
    g.clearRect(0, 0, m.width, m.height);
    if (!state.px) return;
    const [x, y] = state.px, r = Math.max(3, z * 1.5);
    g.lineWidth = 2;
    g.strokeStyle = '#000';
    g.strokeRect(x * z - r, y * z - r, z + 2 * r, z + 2 * r);
    g.strokeStyle = '#ff2d55';
    g.lineWidth = 1.5;
    g.strokeRect(x * z - r + 1, y * z - r + 1, z + 2 * r - 2, z + 2 * r - 2);
  }

  // ---- overlays: heatmaps, the find mask, the diff map ----

  async function loadOverlay(gen) {
    const kind = state.overlay;
    const ctx = $('overlay').getContext('2d');
    if (kind === 'none' || (kind === 'find' && !state.find) || (kind === 'path' && !state.path) ||
        (kind === 'diff' && !state.diff)) {
      clearOverlay('none', kind === 'diff' ? 'tick "compare A with B" to see the diff map' : '');
      return;
    }
    let ov;
    if (kind === 'find') ov = await loadFind(gen);
    else if (kind === 'path') ov = await loadPath(gen);
    else if (kind === 'diff') ov = await loadDiff(gen);
    else ov = await loadHeat(kind, gen);
    if (!ov || gen !== generation) return;
    ctx.clearRect(0, 0, W, H);
    ctx.drawImage(ov.bmp, 0, 0, W, H, 0, 0, W, H);
    $('overlay').dataset.kind = kind;
    $('overlay').style.opacity = String(state.opacity);
    const lg = $('legend');
    if (ov.bmp.height > H) {
      lg.width = W; lg.height = ov.bmp.height - H;
      lg.getContext('2d').drawImage(ov.bmp, 0, H, W, lg.height, 0, 0, W, lg.height);
      lg.style.width = $('image').style.width;
      lg.style.height = (lg.height * parseInt($('image').style.width, 10) / W) + 'px';
    } else {
      lg.width = 0; lg.height = 0; lg.style.height = '0';
    }
    $('legend-text').textContent = ov.legend;
  }

  // No overlay drawn, no legend; kind says why ('none', 'find-error', ...).
  function clearOverlay(kind, legend) {
    $('overlay').getContext('2d').clearRect(0, 0, W, H);
    $('overlay').dataset.kind = kind;
    $('legend-text').textContent = legend || '';
    $('legend').width = 0;
    $('legend').height = 0;
    $('legend').style.height = '0';
  }

  // The B side could not be had (its option text is wrong, say): its
  // image, diff map and summary go; loadPixel drops its tree.
  function clearB() {
    delete images.b;
    $('diff-result').textContent = '';
    if (state.overlay === 'diff') clearOverlay('diff-error');
  }
  function sideError(side, e) {
    return side === 'b' && state.diff ? new ApiError(e.status, 'B: ' + e.message) : e;
  }

  // A heatmap PNG's scale, from its headers: "0 to TOP", and when a few
  // outliers are over the top (X-GGRT-Top below X-GGRT-Max: heatmap.h)
  // how many and how far, counted in the values.
  function scaleText(headers, values) {
    const max = parseFloat(headers.get('X-GGRT-Max')), top = parseFloat(headers.get('X-GGRT-Top'));
    if (!(top < max)) return { top: max, text: '0 to ' + fmtG(max, 4) };
    let n = 0;
    for (const v of values) if (v > top) n++;
    return { top: top, text: '0 to ' + fmtG(top, 4) + ' (the 99.9th percentile; ' + n + ' pixel' +
      (n === 1 ? '' : 's') + ' over it, up to ' + fmtG(max, 4) + ')' };
  }

  async function loadHeat(kind, gen) {
    const params = optParams('a'), key = kind + '|' + keyOf(params);
    if (overlays[key]) return overlays[key];
    if (!(await waitRender(params, kind, 'heatmap of ' + kind, gen))) return null;
    const p = Object.assign({ kind: kind }, params);
    const [png, f32] = await Promise.all([
      api('/api/image', Object.assign({ format: 'png' }, p), 'blob'),
      api('/api/image', Object.assign({ format: 'f32' }, p), 'buf')]);
    const unit = { rays: 'rays', depth: 'deepest ray', time: 'seconds' }[kind];
    const values = new Float32Array(f32.body), sc = scaleText(png.headers, values);
    overlays[key] = {
      bmp: await createImageBitmap(png.body), values: values, max: sc.top,
      legend: kind + ' per pixel (' + unit + '), ' + sc.text, unit: unit,
    };
    status('heatmap of ' + kind + ' ready');
    return overlays[key];
  }

  // Poll a job route until it answers 200; 202 bodies carry the job.
  function waitJob(path, params, label, gen) {
    return pollJob(path, params, label, gen, (r) => r.status === 200, 150);
  }

  // A w x h byte map as an RGBA canvas, colour[v] for value v.
  function maskCanvas(bytes, colours) {
    const c = document.createElement('canvas');
    c.width = W; c.height = H;
    const g = c.getContext('2d'), id = g.createImageData(W, H);
    for (let i = 0; i < W * H; i++) {
      const k = colours[bytes[i]];
      if (!k) continue;
      id.data[4 * i] = k[0]; id.data[4 * i + 1] = k[1]; id.data[4 * i + 2] = k[2]; id.data[4 * i + 3] = 255;
    }
    g.putImageData(id, 0, 0);
    return c;
  }

  // The diff (ggDiff, as ggrt diff): map 1 = the value differs, 2 = the ray tree does.
  async function loadDiff(gen) {
    const params = diffParams(), key = 'diff|' + keyOf(params);
    if (overlays[key]) return overlays[key];
    const r = await waitJob('/api/diff', params, 'diff of A and B', gen);
    if (!r) return null;
    const sum = r.body;
    const [map, f32] = await Promise.all([
      api('/api/diff', Object.assign({ format: 'map' }, params), 'buf'),
      api('/api/diff', Object.assign({ format: 'f32' }, params), 'buf')]);
    const kinds = Object.entries(sum.first_divergence).filter(([, n]) => n > 0)
      .map(([k, n]) => k + ' ' + n).join(', ');
    const text = sum.value_differ + ' of ' + sum.scanned + ' pixels differ in value, ' + sum.tree_differ +
      ' in their ray trees' + (kinds ? ' (first divergence: ' + kinds + ')' : '') +
      '; largest difference ' + fmtG(sum.max_delta, 4);
    $('diff-result').textContent = text;
    const bytes = new Uint8Array(map.body);
    overlays[key] = {
      bmp: await createImageBitmap(maskCanvas(bytes, [null, [245, 158, 11], [192, 38, 211]])),
      values: new Float32Array(f32.body), kinds: bytes,
      legend: 'diff A/B: orange the value differs, magenta the ray tree differs. ' + text,
      unit: '|A-B|', worst: sum.worst,
    };
    status('diff ready');
    return overlays[key];
  }

  // Is the text of the find box (what: 'where') or the path box ('path')
  // well formed? /api/parse says, with the column of an error. While the
  // text is typed (submit false) the error is only marked: selecting its
  // column would have the next keystroke overwrite it. On submit the
  // column is selected.
  async function checkPredicate(text, what, submit) {
    what = what || 'where';
    const box = $(what === 'path' ? 'path-input' : 'find-input'), out = $(what === 'path' ? 'path-result' : 'find-result');
    if (!text) { box.classList.remove('bad'); out.textContent = ''; return false; }
    const r = (await api('/api/parse', { [what]: text })).body[what];
    // An answer for a text since typed over says nothing of the box.
    if (!submit && box.value.trim() !== text) return r.valid;
    box.classList.toggle('bad', !r.valid);
    box.title = r.valid ? '' : r.error;
    if (!r.valid) {
      out.textContent = r.error;
      if (submit && r.column > 0) {
        box.focus();
        box.setSelectionRange(r.column - 1, Math.min(text.length, r.column));
      }
    } else if (out.textContent.match(/^\d+:\d+:/)) {
      out.textContent = '';
    }
    return r.valid;
  }

  async function loadFind(gen) {
    const params = Object.assign({ where: state.find }, optParams('a'));
    const key = 'find|' + keyOf(params);
    if (overlays[key]) return overlays[key];
    let r;
    try {
      r = await waitJob('/api/find', params, 'find', gen);
    } catch (e) {
      if (gen !== generation) return null;
      // The overlay and legend of an earlier find go with it.
      clearOverlay('find-error');
      $('find-input').classList.add('bad');
      $('find-result').textContent = e.message;
      return null;
    }
    if (!r) return null;
    $('find-input').classList.remove('bad');
    const f = r.body;
    const mask = new Uint8Array((await api('/api/find', Object.assign({ format: 'mask' }, params), 'buf')).body);
    const text = f.matched + ' pixel' + (f.matched === 1 ? '' : 's') + ' match';
    $('find-result').textContent = text;
    overlays[key] = {
      bmp: await createImageBitmap(maskCanvas(mask, [null, [255, 45, 85]])), values: mask,
      legend: 'find ' + state.find + ': ' + text, unit: 'match', count: f.matched, matches: f.matches,
    };
    status('find done: ' + text);
    return overlays[key];
  }

  // The path's share heatmap (ggFindPath, as ggrt find --path): the PNG
  // with its legend from the server, the shares as floats for the hover.
  const pathParams = () => Object.assign({ path: state.path, limit: '0' }, optParams('a'));
  async function loadPath(gen) {
    const params = pathParams(), key = 'path|' + keyOf(params);
    if (overlays[key]) return overlays[key];
    let r;
    try {
      r = await waitJob('/api/find', params, 'paths', gen);
    } catch (e) {
      if (gen !== generation) return null;
      clearOverlay('path-error');
      $('path-input').classList.add('bad');
      $('path-result').textContent = e.message;
      return null;
    }
    if (!r) return null;
    $('path-input').classList.remove('bad');
    const [png, f32] = await Promise.all([
      api('/api/find', Object.assign({ format: 'png' }, params), 'blob'),
      api('/api/find', Object.assign({ format: 'share' }, params), 'buf')]);
    const f = r.body, values = new Float32Array(f32.body), sc = scaleText(png.headers, values);
    const text = f.matched + ' pixel' + (f.matched === 1 ? ' has' : 's have') + ' such a path';
    $('path-result').textContent = text;
    $('path-result').dataset.matched = String(f.matched);
    overlays[key] = {
      bmp: await createImageBitmap(png.body), values: values, max: sc.top,
      legend: 'share of each pixel carried by paths ' + state.path + ': ' + text + '; ' + sc.text,
      unit: 'share', count: f.matched,
    };
    status('paths done: ' + text);
    return overlays[key];
  }

  function currentOverlay() {
    const k = state.overlay;
    if (k === 'none') return null;
    if (k === 'find') return overlays['find|' + keyOf(Object.assign({ where: state.find }, optParams('a')))];
    if (k === 'path') return overlays['path|' + keyOf(pathParams())];
    if (k === 'diff') return overlays['diff|' + keyOf(diffParams())];
    return overlays[k + '|' + keyOf(optParams('a'))];
  }

  // ---- hover ----

  // The pixel under the pointer. The browser paints the canvas's box with
  // its edges on whole device pixels (a box laid out at top 60.375 is
  // painted at 60 on a 1x screen, at 60.5 on a 2x one), and the pointer is
  // on one device pixel: its centre, against the painted box, names the
  // image pixel. The position must keep its fraction: pointer events do,
  // but a click's clientX is cut to a whole CSS pixel and its offsetX
  // rounded, half a pixel off on a 2x screen (so the click uses the
  // position of the pointerup before it).
  function pixelAt(cx, cy) {
    const r = $('image').getBoundingClientRect(), dpr = window.devicePixelRatio || 1;
    const at = (v, lo, size, n) => {
      const a = Math.round(lo * dpr), b = Math.round((lo + size) * dpr); // the painted edges
      const dev = Math.floor(v * dpr + 1e-6); // the device pixel under the pointer
      return b > a ? Math.floor((dev + 0.5 - a) / (b - a) * n) : -1;
    };
    const x = at(cx, r.left, r.width, W), y = at(cy, r.top, r.height, H);
    return x >= 0 && y >= 0 && x < W && y < H ? [x, y] : null;
  }
  let lastUp = null; // the last pointerup's position on the image: a click's, with its fraction

  function hover(ev) { hoverAt(pixelAt(ev.clientX, ev.clientY)); }

  let hovered = null; // the pixel the readout is of: said again when the view changes
  function hoverAt(p) {
    const img = images.a;
    if (!p || !img) return;
    hovered = p;
    const i = 3 * (p[1] * W + p[0]);
    let t = 'pixel ' + p[0] + ',' + p[1] + '  ' + [img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]].map((v) => fmtG(v, 9)).join(' ');
    const ov = currentOverlay();
    if (ov) {
      const v = ov.values[p[1] * W + p[0]];
      t += '\n' + (state.overlay === 'find' ? (v ? 'matches ' : 'does not match ') + state.find
        : ov.unit + ' ' + fmtG(v, 6));
      if (ov.kinds) t += ['  same', '  the value differs', '  the ray tree differs'][ov.kinds[p[1] * W + p[0]]];
    }
    if (images.b && state.diff) {
      t += '\nB ' + [images.b.rgb[i], images.b.rgb[i + 1], images.b.rgb[i + 2]].map((v) => fmtG(v, 9)).join(' ');
    }
    $('hover').textContent = t;
  }

  // ---- the selected pixel: trees, views ----

  // The trace document writes NaN and infinities as "nan", "inf", "-inf"
  // (docs/trace-json.md, version 2): numbers again here, in vectors,
  // colours and the number fields, never in names (a group may be "inf").
  const NUMBER_KEYS = new Set(['t', 'n_medium', 'n_other', 'fresnel', 'perr', 'offset', 'tir_margin',
    'edge', 't_block', 'share']);
  const NONFINITE = { inf: Infinity, '-inf': -Infinity, nan: NaN };
  function traceJson(text) {
    return JSON.parse(text, function (k, v) {
      return typeof v === 'string' && v in NONFINITE && (Array.isArray(this) || NUMBER_KEYS.has(k))
        ? NONFINITE[v] : v;
    });
  }
  async function trace(side, extra) {
    const p = Object.assign({ x: state.px[0], y: state.px[1] }, optParams(side), extra || {});
    try {
      return { json: traceJson((await api('/api/trace', p, 'text')).body), note: '' };
    } catch (e) {
      if (e.status !== 413) throw e;
      p.sample = 0;
      return { json: traceJson((await api('/api/trace', p, 'text')).body), note: 'the whole tree is too large: sample 0 only. ' };
    }
  }

  // The trees of the pixels shown last, by their key: Back or Forward to
  // one of them shows it again at once, asking the server nothing.
  const traceCache = new Map(), TRACE_CACHE = 16;
  function keepTraces(t) {
    traceCache.delete(t.key);
    traceCache.set(t.key, t);
    if (traceCache.size > TRACE_CACHE) traceCache.delete(traceCache.keys().next().value);
  }

  async function loadPixel(gen) {
    if (!state.px) {
      if (traces.a) clearPixel();
      return;
    }
    const key = state.px.join(',') + '|' + keyOf(optParams('a')) + '|' + (state.diff ? keyOf(optParams('b')) : '') +
      '|' + state.path;
    drawMarker();
    const kept = traces.key !== key && traceCache.get(key);
    if (kept) {
      keepTraces(kept);
      // A copy: which tab contents are on screen (diagKey, ...) is the copy's.
      traces = Object.assign({}, kept);
    } else if (traces.key !== key) {
      const where = 'pixel ' + state.px.join(',');
      $('pixel-title').textContent = where + ': tracing';
      let a, b = null, cmp = null, paths, bError = null;
      try {
        a = await trace('a');
        if (state.diff) {
          // A failed B (its option text is wrong, say) shows A alone: the
          // B tree and the comparison of before do not stay.
          try {
            b = await trace('b');
            cmp = (await api('/api/compare', Object.assign({ x: state.px[0], y: state.px[1] },
              diffParams()))).body;
          } catch (e) {
            b = cmp = null;
            bError = sideError('b', e);
          }
        }
        paths = state.path ? await pixelPaths(a) : null;
      } catch (e) {
        if (gen === pixelGen) $('pixel-title').textContent = where + ': the trace failed';
        throw e;
      }
      // A B refused for its text is kept with the key; else asked again.
      const t = { key: bError && bError.status !== 400 ? '' : key, a: a, b: b, cmp: cmp, paths: paths,
        bError: bError };
      if (t.key) keepTraces(t);
      if (gen !== pixelGen) return;
      traces = Object.assign({}, t);
    }
    showPixel();
    await showTab(gen);
    if (traces.bError) throw traces.bError;
  }

  // The ledger terms of the selected pixel the path matches (ggrt trace
  // --path's document), or { error } when the path cannot be asked.
  async function pixelPaths(a) {
    if (a.json.sample !== null) return { error: 'the whole tree is too large to match paths in' };
    try {
      return (await api('/api/trace', Object.assign({ x: state.px[0], y: state.px[1], path: state.path },
        optParams('a')))).body;
    } catch (e) {
      return { error: e.message };
    }
  }

  // Mark the rays of box's tree on a matching path (a term's ray and its
  // ancestors) and hide or dim the others; the matching terms above it.
  function filterTree(box, j, p) {
    const parent = {};
    const walk = (n, up) => { parent[n.id] = up; for (const k of n.children) walk(k, n.id); };
    for (const r of j.roots) walk(r, -1);
    const on = new Set();
    for (const t of p.terms || []) for (let id = t.node; id >= 0 && !on.has(id); id = parent[id]) on.add(id);
    for (const d of box.querySelectorAll('details.node')) {
      d.classList.toggle('off-path', !on.has(parseInt(d.dataset.id, 10)));
      d.classList.toggle('on-path', on.has(parseInt(d.dataset.id, 10)));
    }
    box.classList.toggle('path-dim', state.pathDim);
    box.classList.toggle('path-hide', !state.pathDim);
    const s = el('div', 'paths');
    s.id = 'path-summary';
    if (p.error) {
      s.textContent = 'path ' + state.path + ': ' + p.error;
      box.classList.remove('path-dim', 'path-hide');
    } else {
      s.dataset.matched = String(p.matched);
      s.dataset.share = String(p.share);
      s.appendChild(el('div', 'f', 'paths matching ' + p.expression + ': ' + p.matched + ' of ' + p.paths +
        ', carrying ' + fmtG(100 * p.share, 4) + '% of the pixel (' + on.size + ' rays on them)'));
      for (const t of p.terms) {
        const d = el('div', 'f', fmtG(100 * t.share, 4) + '%  ' + t.kind + (t.light >= 0 ? ' of light ' + t.light : '') +
          ' at ray #' + t.node + '  ');
        d.appendChild(el('span', 'ev', t.events));
        s.appendChild(d);
      }
    }
    box.insertBefore(s, box.querySelector('h3').nextSibling);
  }

  // No pixel selected (Back to before the first click): nothing of the
  // last one stays on screen.
  function clearPixel() {
    traces = { key: '', a: null, b: null };
    $('pixel-title').textContent = 'no pixel selected';
    $('pixel-swatch').style.background = '';
    $('pixel-value').textContent = '';
    $('pixel-value').dataset.rgb = '';
    $('pixel-rays').textContent = '';
    for (const id of ['tree-a', 'tree-b', 'ledger', 'diag', 'trace-text']) $(id).textContent = '';
    $('tree-b').hidden = true;
    $('divergence').hidden = true;
    $('svg-view').removeAttribute('src');
    delete $('pixel-head').dataset.pixel;
    document.dispatchEvent(new Event('ggrt:pixel'));
  }

  function showPixel() {
    const a = traces.a.json;
    $('pixel-title').textContent = 'pixel ' + a.pixel.join(',');
    $('pixel-swatch').style.background = srgb(a.color);
    showValue();
    fillTree($('tree-a'), traces.a, state.diff ? 'A' : '');
    $('tree-a').classList.remove('path-dim', 'path-hide');
    if (traces.paths) filterTree($('tree-a'), traces.a.json, traces.paths);
    $('tree-b').hidden = !traces.b;
    if (traces.b) fillTree($('tree-b'), traces.b, 'B');
    const c = traces.cmp;
    $('divergence').hidden = !c;
    if (c) {
      $('divergence').textContent = (c.differ ? 'first divergence: ' : '') + c.text;
      for (const [box, id] of [['tree-a', c.first.node_a], ['tree-b', c.first.node_b]]) {
        const n = id >= 0 && $(box).querySelector('details.node[data-id="' + id + '"]');
        if (n) n.classList.add('diverge');
      }
    }
    $('pixel-head').dataset.pixel = a.pixel.join(',');
    $('pixel-head').dataset.shownAt = performance.now().toFixed(1);
    document.dispatchEvent(new Event('ggrt:pixel'));
  }

  // The value is the rendered image's (what ggrt render writes and
  // --pixel prints) once it is in; until then the trace's own colour.
  function showValue() {
    const a = traces.a.json;
    const v = $('pixel-value'), img = images.a && images.a.q === keyOf(optParams('a')) ? images.a : null;
    const i = 3 * (a.pixel[1] * W + a.pixel[0]);
    const rgb = img ? [img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]] : a.color;
    v.textContent = rgb.map((c) => fmtG(c, 9)).join(' ');
    v.dataset.rgb = img ? v.textContent : '';
    const s = a.stats;
    v.title = 'linear RGB, as ggrt render --pixel prints it';
    // Its own element: spaces in the text would collapse into one.
    $('pixel-rays').textContent = 'rays: eye ' + s.eye + ', reflect ' + s.reflect + ' (tir ' + s.tir +
      ' of them), refract ' + s.refract + ', shadow ' + s.shadow;
  }

  function objName(i) {
    const o = scene && scene.shapes[i];
    if (!o) return 'object #' + i;
    return o.kind + ' #' + i + (o.line > 0 ? ' (line ' + o.line + ')' : '');
  }

  function field(parent, label, text, extra) {
    const d = el('div', 'f');
    if (label) d.appendChild(el('b', '', label + ' '));
    d.appendChild(document.createTextNode(text));
    if (extra) for (const e of extra) d.appendChild(e);
    parent.appendChild(d);
    return d;
  }

  function nodeEl(n, open) {
    const d = el('details', 'node kind-' + n.kind);
    d.dataset.id = n.id;
    d.open = open(n);
    const s = el('summary');
    s.appendChild(el('span', 'kind', n.kind + (n.channel ? ' [' + n.channel + ']' : '')));
    // weight: the factor of this ray's colour in the pixel; share: the
    // part of the pixel it carries (the ledger's measure); factor: its
    // weight in its parent's colour (docs/trace-json.md).
    s.appendChild(document.createTextNode(' #' + n.id + ' depth ' + n.depth +
      '  weight ' + col(n.weight) + '  share ' + fmtG(100 * n.share, 3) + '%' +
      (n.depth > 1 ? '  factor ' + col(n.factor) : '') + '  ' +
      (n.hit ? '\u2192 ' + objName(n.hit.object) + ' at t ' + g6(n.hit.t) + (n.hit.front ? '' : ', back face')
        : '\u2192 missed') + '  returns '));
    s.appendChild(swatch(n.color));
    s.appendChild(document.createTextNode(col(n.color)));
    d.appendChild(s);
    field(d, 'ray', 'o ' + vec(n.origin) + ' d ' + vec(n.direction) + ' in ' +
      (n.medium < 0 ? 'outside' : 'material ' + n.medium) + ' (n ' + g6(n.n_medium) + ')');
    const h = n.hit;
    if (!h) {
      field(d, 'missed', 'background');
    } else {
      const m = scene && scene.materials[h.material];
      field(d, 'hit', objName(h.object) + ' ' + h.shape + ' at t ' + g6(h.t) + ', ' + (h.front ? 'front' : 'back') + ' face');
      if (h.face) {
        // As ggrt trace's text: triangle, the file's face, its line, group, material.
        const fc = h.face;
        field(d, '', 'triangle ' + fc.triangle + ': face ' + fc.index + ' of ' + fc.mesh +
          (fc.line > 0 ? ' (line ' + fc.line + ')' : '') + (fc.group ? ", group '" + fc.group + "'" : '') +
          (fc.material_name ? ", usemtl '" + fc.material_name + "'" : '')).classList.add('face');
      }
      field(d, 'p', vec(h.point) + '  uv (' + h.uv.map(g4).join(', ') + ')');
      field(d, 'ng', vec(h.ng) + '  ns ' + vec(h.ns));
      field(d, 'material', h.material + (m ? ': kd ' + g6(m.kd) + ' ks ' + g6(m.ks) + ' kt ' + g6(m.kt) + ' ior ' + g6(m.ior) : '') +
        ', surface colour ' + col(h.surface), [swatch(h.surface)]);
      const em = h.emission.some((v) => v !== 0);
      field(d, 'ambient', col(h.ambient) + (em ? '  emission ' + col(h.emission) : ''));
      for (const L of h.lights) {
        let t = ' ' + L.verdict;
        if (L.occluder !== null) {
          // a visible light's occluder: a transparent object crossed without loss
          t += (L.verdict === 'visible' ? ' through ' : ' by ') + objName(L.occluder) + ' at t ' + g4(L.t_block);
        }
        if (L.verdict === 'attenuated') t += ', transmittance ' + col(L.transmittance);
        if (L.verdict === 'visible' || L.verdict === 'attenuated') {
          t += '  diffuse ' + col(L.diffuse);
          if (L.phong.some((v) => v !== 0)) t += ' phong ' + col(L.phong);
        }
        const f = field(d, 'light ' + L.light + ':', '');
        f.appendChild(el('span', 'v-' + L.verdict, t));
      }
      if (h.fresnel !== null) {
        field(d, 'fresnel', 'R ' + g6(h.fresnel) + ', T ' + g6(1 - h.fresnel) + ' (n ' + g6(n.n_medium) + ' \u2192 ' + g6(h.n_other) + ')');
      }
    }
    if (n.stop !== 'none' && n.stop !== 'miss') {
      field(d, '', '', [el('span', 'stop', 'stops: ' + (n.stop === 'depth' ? 'depth limit reached'
        : n.stop === 'matte' ? 'no ks or kt: no secondary rays' : n.stop))]);
    }
    if (n.absorption.some((v) => v !== 1)) field(d, 'absorption', 'over the segment ' + col(n.absorption));
    if (h && h.numeric) field(d, 'numeric', numericText(h.numeric)).classList.add('numeric');
    if (n.traversal) field(d, 'traversal', n.traversal.nodes + ' nodes, ' + n.traversal.prims + ' prims tested');
    field(d, 'returns', col(n.color), [swatch(n.color)]);
    for (const k of n.children) d.appendChild(nodeEl(k, open));
    return d;
  }

  // A hit's numeric state as ggrt trace's text says it: the hit point's
  // error bound, the offset of the rays leaving it, the TIR margin and the
  // distance to an edge where they apply.
  function numericText(q) {
    let t = 'perr ' + fmtG(q.perr, 2) + ', offset ' + fmtG(q.offset, 2);
    if (q.tir_margin !== null && isFinite(q.tir_margin)) t += ', tir margin ' + (q.tir_margin >= 0 ? '+' : '') + fmtG(q.tir_margin, 3);
    if (q.edge !== null && isFinite(q.edge)) t += ', edge ' + fmtG(q.edge, 3);
    return t;
  }

  function countNodes(n) { return 1 + n.children.reduce((a, k) => a + countNodes(k), 0); }

  function fillTree(box, t, label) {
    const j = t.json;
    box.textContent = '';
    const total = j.roots.reduce((a, r) => a + countNodes(r), 0);
    const open = total <= 80 ? () => true : (n) => n.depth <= 2;
    const h = el('h3', '', (label ? label + ': ' : '') + total + ' rays, colour ' + j.color.map((c) => fmtG(c, 9)).join(' '));
    box.appendChild(h);
    if (t.note) box.appendChild(el('div', 'stop', t.note));
    for (const r of j.roots) {
      if (j.roots.length > 1) box.appendChild(el('div', 'f', 'sample ' + r.sample));
      box.appendChild(nodeEl(r, open));
    }
  }

  // The tab buttons and panels as state.tab says.
  function showTabs() {
    for (const b of $('tabs').querySelectorAll('button')) b.classList.toggle('active', b.dataset.tab === state.tab);
    for (const t of TABS) $('tab-' + t).hidden = t !== state.tab;
  }

  function setTab(tab) {
    state.tab = tab;
    showTabs();
    writeHash(true);
    const gen = pixelGen;
    showTab(gen).then(() => { if (gen === pixelGen) clearError('pixel'); },
      (e) => { if (gen === pixelGen) fail(e, 'pixel'); });
  }

  let svgUrl = null;
  async function showTab(gen) {
    if (!state.px || !traces.a) return;
    const p = Object.assign({ x: state.px[0], y: state.px[1] }, optParams('a'));
    if (traces.a.json.sample !== null) p.sample = traces.a.json.sample;
    if (state.tab === 'rays3d' && window.ggrtView3d) window.ggrtView3d.draw();
    if (state.tab === 'ledger') showLedger();
    if (state.tab === 'diag' && traces.diagKey !== traces.key) {
      const r = await api('/api/check', Object.assign({ x: state.px[0], y: state.px[1] }, optParams('a')));
      if (gen !== pixelGen) return;
      showDiagnostics(r.body);
      traces.diagKey = traces.key;
    }
    if (state.tab === 'views' && traces.svgKey !== traces.key) {
      const r = await api('/api/trace', Object.assign({ format: 'svg' }, p), 'blob');
      if (gen !== pixelGen) return;
      if (svgUrl) URL.revokeObjectURL(svgUrl);
      svgUrl = URL.createObjectURL(r.body);
      $('svg-view').src = svgUrl;
      traces.svgKey = traces.key;
    }
    if (state.tab === 'text' && traces.textKey !== traces.key) {
      const r = await api('/api/trace', Object.assign({ format: 'text' }, p), 'text');
      if (gen !== pixelGen) return;
      $('trace-text').textContent = r.body;
      traces.textKey = traces.key;
    }
  }

  // The ledger: the pixel's colour term by term (ggLedgerCreate, as ggrt trace --ledger).
  function showLedger() {
    const box = $('ledger'), L = traces.a && traces.a.json.ledger;
    box.textContent = '';
    if (!L) {
      box.appendChild(el('p', 'stop', 'The ledger covers the whole pixel: it needs every sample traced.'));
      return;
    }
    const t = el('table', 'kv'), head = el('tr');
    for (const h of ['share', 'term', 'light', 'carried by', 'value']) head.appendChild(el('th', '', h));
    t.appendChild(head);
    for (const term of L.terms) {
      const tr = el('tr');
      tr.appendChild(el('td', '', (100 * term.share).toFixed(2) + '%'));
      tr.appendChild(el('td', '', term.kind + (term.object >= 0 ? ' at ' + objName(term.object) : '')));
      tr.appendChild(el('td', '', term.light >= 0 ? String(term.light) : ''));
      tr.appendChild(el('td', '', '#' + term.node + ' ' + term.path));
      const v = el('td');
      v.appendChild(swatch(term.value));
      v.appendChild(document.createTextNode(col(term.value)));
      tr.appendChild(v);
      t.appendChild(tr);
    }
    box.appendChild(t);
    const sum = el('p', 'f');
    sum.textContent = L.terms.length + ' terms; sum ' + L.sum.map((c) => fmtG(c, 9)).join(' ') + ', pixel ' +
      L.pixel.map((c) => fmtG(c, 9)).join(' ') + ', rounding bound ' + L.bound.map((c) => fmtG(c, 3)).join(' ') +
      (L.holds ? ': they add up to the pixel' : ': they do NOT add up to the pixel');
    sum.dataset.holds = L.holds ? '1' : '0';
    box.appendChild(sum);
  }

  // The invariants at this pixel (ggCheck of the pixel, as ggrt check --crop).
  function showDiagnostics(c) {
    const box = $('diag');
    box.textContent = '';
    const t = el('table', 'kv'), head = el('tr');
    for (const h of ['invariant', 'severity', 'rays', 'worst', 'where']) head.appendChild(el('th', '', h));
    t.appendChild(head);
    let bad = 0;
    for (const it of c.invariants) {
      const tr = el('tr', it.pixels ? 'sev-' + it.severity : 'ok');
      const w = it.worst_pixels[0];
      tr.appendChild(el('td', '', it.name));
      tr.appendChild(el('td', '', it.severity));
      tr.appendChild(el('td', '', it.pixels ? String(it.rays) : 'holds'));
      tr.appendChild(el('td', '', it.pixels ? fmtG(it.worst, 4) : ''));
      tr.appendChild(el('td', '', w ? (w.node >= 0 ? 'ray #' + w.node : 'the pixel') +
        (w.object >= 0 ? ', ' + objName(w.object) : '') + (w.line > 0 ? ', line ' + w.line : '') : ''));
      if (it.pixels) bad++;
      t.appendChild(tr);
    }
    box.appendChild(el('p', 'f', bad ? bad + ' invariant' + (bad === 1 ? '' : 's') + ' fail here' :
      'every invariant holds at this pixel'));
    box.appendChild(t);
    // null: no bound (ggrt check: ks + kt >= 1 somewhere lets a ray's light grow)
    box.appendChild(el('p', 'hint', 'radiance bound of the scene: ' + (c.radiance_bound === null ||
      c.radiance_bound === undefined ? 'unbounded (ks + kt >= 1 lets a ray\'s light grow without bound)'
      : fmtG(c.radiance_bound, 4)) +
      '. The whole image: /api/check (ggrt check).'));
  }

  // The 3D view is view3d.js (WebGL); links.js links it, the tree and
  // the image; export.js saves what is shown. They see the page through
  // window.ggrt and the ggrt:ready / ggrt:pixel / ggrt:image events.

  // ---- putting it together ----

  function fail(e, from) {
    showError(e && e.message ? e.message : String(e), from);
    status('error');
  }

  // Bring everything on screen up to date with state; push: a new
  // history entry (writeHash).
  async function refresh(push) {
    const gen = ++generation;
    showError('');
    writeHash(push);
    $('overlay-select').value = state.overlay;
    $('opacity').value = String(state.opacity);
    $('diff-on').checked = state.diff;
    $('find-input').value = state.find;
    $('path-input').value = state.path;
    $('path-dim').checked = state.pathDim;
    fillPanel('a');
    fillPanel('b');
    // The pixel's tree first: a trace is one pixel's work, the image may
    // take minutes.
    const pg = ++pixelGen;
    const pixel = loadPixel(pg).catch((e) => { if (pg === pixelGen) fail(e, 'pixel'); });
    try {
      const img = await loadImage('a', gen);
      if (!img || gen !== generation) return;
      drawImage();
      if (traces.a && pg === pixelGen) showValue();
      if (state.diff) {
        try {
          await loadImage('b', gen);
        } catch (e) {
          // B cannot be rendered: nothing of the B before it stays on screen.
          if (gen === generation) clearB();
          throw sideError('b', e);
        }
      }
      await loadOverlay(gen);
      if (gen === generation) hoverAt(hovered); // without what the view no longer shows (diff off: B)
      await pixel;
    } catch (e) {
      if (gen === generation) fail(e, 'view');
    }
    await pixel;
  }

  function select(x, y) {
    state.px = [Math.max(0, Math.min(W - 1, x)), Math.max(0, Math.min(H - 1, y))];
    writeHash(true);
    drawMarker();
    hoverAt(state.px);
    const gen = ++pixelGen;
    // The pixel's trees in, the error of an earlier pixel's goes.
    loadPixel(gen).then(() => { if (gen === pixelGen) clearError('pixel'); },
      (e) => { if (gen === pixelGen) fail(e, 'pixel'); });
  }

  function keys(e) {
    const t = e.target.tagName;
    if (t === 'INPUT' || t === 'SELECT' || t === 'TEXTAREA' || e.ctrlKey || e.metaKey || e.altKey) return;
    const step = e.shiftKey ? 10 : 1, p = state.px || [Math.floor(W / 2), Math.floor(H / 2)];
    const moves = { ArrowLeft: [-step, 0], ArrowRight: [step, 0], ArrowUp: [0, -step], ArrowDown: [0, step] };
    if (moves[e.key]) {
      e.preventDefault();
      select(p[0] + moves[e.key][0], p[1] + moves[e.key][1]);
    } else if (e.key === 'o') {
      // The next overlay with something to show: find, path and diff only
      // once there is a find, a path or a B side (the list chooses them all).
      const shown = OVERLAYS.filter((o) => (o !== 'find' || state.find) && (o !== 'path' || state.path) &&
        (o !== 'diff' || state.diff));
      state.overlay = shown[(shown.indexOf(state.overlay) + 1) % shown.length];
      refresh(true);
    } else if (e.key === '+' || e.key === '=' || e.key === '-') {
      // From the zoom on screen (fitted or chosen), one step, within 1..ZOOM_MAX.
      const z = Math.max(1, Math.round(parseFloat($('image').style.width) / W) || 1);
      state.zoom = Math.max(1, Math.min(Math.max(ZOOM_MAX, z), z + (e.key === '-' ? -1 : 1)));
      drawImage();
      writeHash();
    } else if (e.key >= '1' && e.key <= '6') {
      const b = $('tabs').querySelectorAll('button')[parseInt(e.key, 10) - 1];
      if (b && !b.hidden) setTab(b.dataset.tab);
    } else if (e.key === 'e' || e.key === 'c') {
      for (const d of document.querySelectorAll('.tree details')) d.open = e.key === 'e';
    } else if (e.key === 'f') {
      e.preventDefault();
      $('find-input').focus();
    } else if (e.key === 'p') {
      e.preventDefault();
      $('path-input').focus();
    } else if (e.key === '?') {
      $('help').showModal();
    }
  }

  function wire() {
    $('image').addEventListener('pointermove', hover);
    $('image').addEventListener('pointerup', (e) => { lastUp = [e.clientX, e.clientY]; });
    $('image').addEventListener('click', (e) => {
      // The click's own position is whole CSS pixels: the pointerup's, when it is that one.
      const up = lastUp && Math.abs(lastUp[0] - e.clientX) < 1 && Math.abs(lastUp[1] - e.clientY) < 1;
      const p = up ? pixelAt(lastUp[0], lastUp[1]) : pixelAt(e.clientX, e.clientY);
      lastUp = null;
      // When the click came and (showPixel) when its tree was shown, in
      // the page's own clock: what a user waits, without a test's polling.
      $('pixel-head').dataset.clickedAt = performance.now().toFixed(1);
      if (p) select(p[0], p[1]);
      $('image').focus();
    });
    document.addEventListener('keydown', keys);
    $('overlay-select').addEventListener('change', (e) => {
      state.overlay = e.target.value;
      if (state.overlay === 'diff' && !state.diff) { state.diff = true; $('diff-panel').open = true; }
      if (state.overlay === 'find' && !state.find) $('find-input').focus();
      if (state.overlay === 'path' && !state.path) $('path-input').focus();
      refresh(true);
    });
    $('opacity').addEventListener('input', (e) => {
      state.opacity = parseFloat(e.target.value);
      $('overlay').style.opacity = String(state.opacity);
      writeHash();
    });
    $('zoom').addEventListener('change', (e) => { state.zoom = parseInt(e.target.value, 10); drawImage(); writeHash(); });
    // The predicate is checked as it is typed (/api/parse answers 200
    // either way), and only a valid one is searched for.
    let typing = null;
    $('find-input').addEventListener('input', () => {
      clearTimeout(typing);
      typing = setTimeout(() => checkPredicate($('find-input').value.trim())
        .then(() => clearError('find'), (e) => fail(e, 'find')), 250);
    });
    $('find-form').addEventListener('submit', async (e) => {
      e.preventDefault();
      const text = $('find-input').value.trim();
      try {
        if (text && !(await checkPredicate(text, 'where', true))) return;
      } catch (err) {
        fail(err, 'find');
        return;
      }
      // An empty box takes the find away, as the path box does.
      state.find = text;
      if (text) state.overlay = 'find';
      else if (state.overlay === 'find') state.overlay = 'none';
      $('find-result').textContent = !text ? '' : imageReady() ? 'searching…'
        : 'waits for the image (rendering)';
      refresh(true);
    });
    let typingPath = null;
    $('path-input').addEventListener('input', () => {
      clearTimeout(typingPath);
      typingPath = setTimeout(() => checkPredicate($('path-input').value.trim(), 'path')
        .then(() => clearError('find'), (e) => fail(e, 'find')), 250);
    });
    $('path-form').addEventListener('submit', async (e) => {
      e.preventDefault();
      const text = $('path-input').value.trim();
      try {
        if (text && !(await checkPredicate(text, 'path', true))) return;
      } catch (err) {
        fail(err, 'find');
        return;
      }
      // An empty box takes the filter away.
      state.path = text;
      if (text) state.overlay = 'path';
      else if (state.overlay === 'path') state.overlay = 'none';
      $('path-result').textContent = !text ? '' : imageReady() ? 'searching…'
        : 'waits for the image (rendering)';
      refresh(true);
    });
    $('path-dim').addEventListener('change', (e) => {
      state.pathDim = e.target.checked;
      writeHash();
      if (traces.paths && !traces.paths.error) {
        $('tree-a').classList.toggle('path-dim', state.pathDim);
        $('tree-a').classList.toggle('path-hide', !state.pathDim);
      }
    });
    $('render-a').addEventListener('click', () => { state.a = readPanel('a'); refresh(true); });
    $('reset-a').addEventListener('click', () => { state.a = ''; refresh(true); });
    $('render-b').addEventListener('click', () => {
      state.b = readPanel('b');
      state.diff = true;
      state.overlay = 'diff';
      refresh(true);
    });
    $('diff-on').addEventListener('change', (e) => {
      state.diff = e.target.checked;
      if (state.diff) state.b = readPanel('b');
      if (!state.diff && state.overlay === 'diff') state.overlay = 'none';
      refresh(true);
    });
    for (const b of $('tabs').querySelectorAll('button')) b.addEventListener('click', () => setTab(b.dataset.tab));
    $('help-button').addEventListener('click', () => $('help').showModal());
    $('help-close').addEventListener('click', () => $('help').close());
    // Back, Forward, a link or an address changed by hand: the whole view
    // follows the address (the pixel and its tree, the tabs, the options
    // and diff panels, the 3D camera), as on a load. Restoring only
    // replaces the entry (refresh without push), so it never adds one;
    // the jobs of the view left are cancelled as for any newer view. The
    // browser fires popstate and then, the fragment having changed,
    // hashchange for the same step: the view is restored once.
    let restored = null;
    const restore = () => {
      readHash();
      showTabs();
      if (state.diff) $('diff-panel').open = true;
      document.dispatchEvent(new Event('ggrt:hash'));
      refresh();
    };
    window.addEventListener('popstate', () => { restored = location.href; restore(); });
    window.addEventListener('hashchange', (e) => {
      if (e.newURL === restored) { restored = null; return; }
      restore();
    });
    window.addEventListener('resize', () => { if (!state.zoom) drawImage(); });
  }

  async function start() {
    try {
      info = (await api('/api/info')).body;
      scene = (await api('/api/scene')).body;
    } catch (e) {
      fail(e);
      return;
    }
    W = info.width; H = info.height;
    document.title = 'ggrt serve: ' + info.scene;
    $('scene-name').textContent = info.scene + ', ' + W + 'x' + H + ', ' + info.objects + ' objects';
    serverOpts = parseText(info.options);
    buildPanel('a');
    buildPanel('b');
    readHash();
    sizeCanvases(); // a click can pick a pixel before the image is in
    wire();
    showTabs();
    if (state.diff) $('diff-panel').open = true;
    window.ggrt = {
      api: api, state: state, info: info, scene: scene, W: W, H: H, select: select, overlay: currentOverlay,
      imageReady: imageReady, cancelJob: cancelJob,
      get traces() { return traces; },
    };
    document.dispatchEvent(new Event('ggrt:ready'));
    await refresh();
  }

  start();
})();
