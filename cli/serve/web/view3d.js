// SPDX-License-Identifier: MIT
// ggrt serve: the 3D view. The scene (/api/scene) shaded with WebGL (one
// Lambert shader, meshes as their triangles, implicit surfaces as the
// library's triangulation of f = 0, textured surfaces with their
// texture where the renderer puts it), and over it, on a 2D canvas,
// the selected pixel's rays coloured by kind, the shadow rays, the lights
// and the camera's frustum. Linked to the tree: the node under the mouse
// (or picked with j/k) is drawn thick; a click on a segment selects its
// node. The orbit camera is kept in the address (#cam=...). No library.
'use strict';
(function () {
  const $ = (id) => document.getElementById(id);
  const KIND = { eye: '#111111', reflect: '#1f5fd0', refract: '#17a34a', tir: '#c026d3' };
  const LIGHT = { visible: '#f59e0b', attenuated: '#b45309', blocked: '#dc2626' };
  const MAX_TRIS = 150000; // triangles the view builds from analytic shapes

  // ---- a tiny mat4 (column-major, as WebGL wants it), in doubles: a
  // camera 3e7 from a scene of size 1 (acc-distant.nff) needs them until
  // the product, which alone goes to the GPU as floats ----
  const M = {
    mul(a, b) {
      const r = new Float64Array(16);
      for (let i = 0; i < 4; i++) {
        for (let j = 0; j < 4; j++) {
          let s = 0;
          for (let k = 0; k < 4; k++) s += a[k * 4 + j] * b[i * 4 + k];
          r[i * 4 + j] = s;
        }
      }
      return r;
    },
    perspective(fovy, aspect, near, far) {
      const f = 1 / Math.tan(fovy / 2), r = new Float64Array(16);
      r[0] = f / aspect; r[5] = f; r[10] = (far + near) / (near - far); r[11] = -1;
      r[14] = 2 * far * near / (near - far);
      return r;
    },
    lookAt(e, t, up) {
      const f = V.norm(V.sub(t, e)), s = V.norm(V.cross(f, up)), u = V.cross(s, f);
      return new Float64Array([s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
        -V.dot(s, e), -V.dot(u, e), V.dot(f, e), 1]);
    },
    apply(m, p) {
      return [0, 1, 2, 3].map((i) => m[i] * p[0] + m[4 + i] * p[1] + m[8 + i] * p[2] + m[12 + i]);
    },
  };
  const V = {
    sub: (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]],
    add: (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]],
    mul: (a, s) => [a[0] * s, a[1] * s, a[2] * s],
    dot: (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2],
    cross: (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]],
    len: (a) => Math.hypot(a[0], a[1], a[2]),
    norm: (a) => { const l = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / l, a[1] / l, a[2] / l]; },
    perp: (a) => V.norm(V.cross(a, Math.abs(a[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0])),
  };

  const view = {
    gl: null, prog: null, buf: null, stride: 11, opaque: 0, clear: 0, groups: [], tex: [], lines: null, baseNote: '',
    yaw: 0, pitch: 0, dist: 10, target: [0, 0, 0], up: [0, 0, 1], e1: [1, 0, 0], e2: [0, 1, 0],
    fov: 0, // the scene camera's field of view (degrees, across) when looking through it; 0: 45 up
    set: false, mvp: null, hl: -1, hlObject: -1, segs: [], triangles: 0, built: false,
  };
  window.ggrtView3d = view;

  // ---- geometry: every shape as triangles ----
  // A vertex: position, normal, rgba, object, and for a textured surface
  // its texture coordinates t and their kind k: view.stride floats, 11
  // for a scene without textures (as before textures were drawn), 15 with
  // t and k. k = 0: untextured. 1: t.xy is (u, v), interpolated over the
  // triangle: on the planar shapes and mesh triangles the renderer's
  // (u, v) is affine over each triangle it hits, so interpolating the
  // corners' (u, v), which the server computes with the library
  // (ggSceneObjectUV), gives it exactly. 2 (sphere), 3 (cone): t is the
  // point in the shape's frame (e1, e2, axis; /api/scene), which is
  // affine, and the fragment shader turns it into (u, v) by the
  // library's formulas (atan2 and acos are not affine: interpolated
  // (u, v) would smear across the seam and the poles).
  function builder() {
    const a = [], tk = view.stride === 15;
    const put = (v, nn, c, obj, t, k) => {
      a.push(v[0], v[1], v[2], nn[0], nn[1], nn[2], c[0], c[1], c[2], c[3], obj);
      if (!tk) return;
      if (t) a.push(t[0], t[1], t[2], k); else a.push(0, 0, 0, 0);
    };
    return {
      // tc: the three corners' t (or undefined), k their kind.
      tri(p, q, r, c, obj, nrm, tc, k) {
        const nn = nrm || V.norm(V.cross(V.sub(q, p), V.sub(r, p)));
        put(p, nn, c, obj, tc && tc[0], k); put(q, nn, c, obj, tc && tc[1], k); put(r, nn, c, obj, tc && tc[2], k);
      },
      vert: put,
      data: a,
    };
  }
  function matColour(scene, m) {
    const mt = scene.materials[m];
    if (!mt) return [0.7, 0.7, 0.7, 1];
    const c = mt.color.map((v) => Math.min(1, Math.max(0, v)));
    if (mt.kt > 0.2) return [0.45 + 0.3 * c[0], 0.65 + 0.2 * c[1], 0.85 + 0.1 * c[2], 0.45];
    if (mt.kd < 0.05 && mt.ks > 0.5) return [0.55 * c[0] + 0.25, 0.55 * c[1] + 0.25, 0.55 * c[2] + 0.3, 1];
    return [0.2 + 0.8 * c[0], 0.2 + 0.8 * c[1], 0.2 + 0.8 * c[2], 1];
  }
  // The texture object s shows in the view, or -1: its material's, if
  // /api/scene describes it (an image or a checker) and gives s what the
  // view needs to place it (mesh: its part m, listed).
  function texOf(scene, s, m) {
    const mt = scene.materials[s.material], t = mt && mt.texture;
    const d = t >= 0 && scene.textures && scene.textures[t];
    if (!d || (d.kind !== 'image' && d.kind !== 'checker')) return -1;
    const n = s.verts ? s.verts.length : 0, uv = s.uv ? s.uv.length : -1;
    const ok = s.kind === 'sphere' || s.kind === 'cone' ? !!s.e1
      : s.kind === 'mesh' ? !!(m && m.uv && m.uv.length * 3 === m.verts.length * 2)
        : s.kind === 'rect' ? uv === 8 : s.kind === 'implicit' ? uv === 2
          : uv === (s.kind === 'triangle' && n > 3 ? 6 * (n - 2) : 2 * n);
    return ok ? t : -1;
  }
  // A textured surface's colour: the material's own (the texture
  // multiplies it, as in the renderer), with matColour's opacity.
  function texColour(scene, m) {
    const c = scene.materials[m].color.map((v) => Math.min(1, Math.max(0, v)));
    return [c[0], c[1], c[2], matColour(scene, m)[3]];
  }
  // (u, v) pairs i, j, k of a flat list as the corners' t.
  const uvs = (uv, i, j, k) => [i, j, k].map((n) => [uv[2 * n], uv[2 * n + 1], 0]);
  function sphere(b, s, c, obj, seg, tex) {
    const P = (i, j) => {
      const th = Math.PI * j / (seg / 2), ph = 2 * Math.PI * i / seg;
      return [Math.sin(th) * Math.cos(ph), Math.sin(th) * Math.sin(ph), Math.cos(th)];
    };
    // t: the direction in the sphere's (u, v) frame (u about e1 x e2 from e1).
    const e3 = tex ? V.cross(s.e1, s.e2) : null;
    const T = (d) => [V.dot(d, s.e1), V.dot(d, s.e2), V.dot(d, e3)];
    const k = tex ? 2 : 0;
    for (let j = 0; j < seg / 2; j++) {
      for (let i = 0; i < seg; i++) {
        const n = [P(i, j), P(i + 1, j), P(i + 1, j + 1), P(i, j + 1)];
        const p = n.map((d) => V.add(s.center, V.mul(d, s.radius)));
        const t = tex ? n.map(T) : [];
        b.vert(p[0], n[0], c, obj, t[0], k); b.vert(p[2], n[2], c, obj, t[2], k); b.vert(p[1], n[1], c, obj, t[1], k);
        b.vert(p[0], n[0], c, obj, t[0], k); b.vert(p[3], n[3], c, obj, t[3], k); b.vert(p[2], n[2], c, obj, t[2], k);
      }
    }
  }
  function cone(b, s, c, obj, seg, tex) {
    const ax = V.norm(V.sub(s.apex, s.base)), p = V.perp(ax), q = V.cross(ax, p);
    const h = V.len(V.sub(s.apex, s.base));
    const at = (ctr, r, t) => V.add(ctr, V.add(V.mul(p, r * Math.cos(t)), V.mul(q, r * Math.sin(t))));
    // t: the point about the base in the cone's frame, height over h.
    const T = (x) => { const w = V.sub(x, s.base); return [V.dot(w, s.e1), V.dot(w, s.e2), V.dot(w, ax) / h]; };
    for (let i = 0; i < seg; i++) {
      const t0 = 2 * Math.PI * i / seg, t1 = 2 * Math.PI * (i + 1) / seg;
      const a0 = at(s.base, s.radius, t0), a1 = at(s.base, s.radius, t1);
      const b0 = at(s.apex, s.radius2, t0), b1 = at(s.apex, s.radius2, t1);
      b.tri(a0, a1, b1, c, obj, null, tex && [a0, a1, b1].map(T), 3);
      b.tri(a0, b1, b0, c, obj, null, tex && [a0, b1, b0].map(T), 3);
    }
  }
  function box(b, lo, hi, c, obj, t) {
    const P = (i) => [i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]];
    const tc = t && [t, t, t];
    for (const [i, j, k, l] of [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]) {
      b.tri(P(i), P(j), P(k), c, obj, null, tc, 1);
      b.tri(P(i), P(k), P(l), c, obj, null, tc, 1);
    }
  }
  // tex: whether to texture it (texOf).
  function shape(b, scene, s, i, seg, c, tex) {
    const uv = tex && s.uv;
    if (s.kind === 'sphere') sphere(b, s, c, i, seg, tex);
    else if (s.kind === 'cone') cone(b, s, c, i, seg, tex);
    else if (s.kind === 'rect') {
      // uv: the corners a, a + e1, a + e1 + e2, a + e2.
      const a = s.corner, p = V.add(a, s.e1), d = V.add(a, s.e2), e = V.add(p, s.e2);
      b.tri(a, p, e, c, i, null, uv && uvs(uv, 0, 1, 2), 1); b.tri(a, e, d, c, i, null, uv && uvs(uv, 0, 2, 3), 1);
    } else if (s.kind === 'implicit' && s.surface) {
      // The library's triangulation of f = 0 (ggSceneObjectTriangulate),
      // shaded with the renderer's normals (the gradient of f at each
      // vertex); its (u, v) is the one pair every hit has.
      const v = s.surface.verts, n = s.surface.normals, t = s.surface.tris;
      const tc = uv && [uv[0], uv[1], 0];
      for (let k = 0; k < t.length; k++) {
        const q = 3 * t[k];
        b.vert([v[q], v[q + 1], v[q + 2]], [n[q], n[q + 1], n[q + 2]], c, i, tc, 1);
      }
      return 'surface';
    } else if (s.kind === 'implicit') {
      box(b, s.lo, s.hi, [c[0], c[1], c[2], 0.25], i, uv && [uv[0], uv[1], 0]);
      return 'implicit';
    } else if (s.verts && s.verts.length >= 3) {
      // A triangle object of more than 3 vertices is the renderer's fan,
      // with (u, v) per fan triangle (6 numbers each); else per vertex.
      const n = s.verts.length, fan = s.kind === 'triangle' && n > 3;
      for (let k = 1; k + 1 < n; k++) {
        const tc = uv && (fan ? uvs(uv, 3 * (k - 1), 3 * (k - 1) + 1, 3 * (k - 1) + 2) : uvs(uv, 0, k, k + 1));
        b.tri(s.verts[0], s.verts[k], s.verts[k + 1], c, i, null, tc, 1);
      }
    }
    return '';
  }

  // The triangles in draw groups: opaque before see-through, each
  // untextured first, then one group per texture. Returns the vertex data;
  // view.groups lists {first, count, clear, tex}.
  function build(scene) {
    const groups = new Map(), shapes = scene.shapes || [];
    const group = (clear, tex) => {
      const key = (clear ? 1 : 0) + ':' + tex;
      if (!groups.has(key)) groups.set(key, { clear: clear, tex: tex, b: builder() });
      return groups.get(key).b;
    };
    const spheres = shapes.filter((s) => s && (s.kind === 'sphere' || s.kind === 'cone')).length;
    // Spheres and cones get fewer segments when there are many of them.
    const seg = Math.max(6, Math.min(32, 2 * Math.floor(Math.sqrt(MAX_TRIS / 2 / Math.max(1, spheres)) / 2)));
    const meshes = {};
    for (const m of scene.meshes || []) meshes[m.object] = m;
    view.stride = shapes.some((s, i) => s && texOf(scene, s, meshes[i]) >= 0) ? 15 : 11;
    let implicit = 0, textured = 0;
    view.meshTriangles = 0;
    view.surfaceTriangles = 0;
    shapes.forEach((s, i) => {
      if (!s) return;
      const m = meshes[i], tex = texOf(scene, s, m);
      const c = tex >= 0 ? texColour(scene, s.material) : matColour(scene, s.material);
      const b = group(c[3] < 1 || (s.kind === 'implicit' && !s.surface) || (s.kind === 'mesh' && !m), tex);
      if (tex >= 0) textured++;
      if (s.kind === 'mesh' && m) {
        const v = m.verts, uv = tex >= 0 ? m.uv : null;
        view.meshTriangles += v.length / 9;
        for (let k = 0, t = 0; k + 8 < v.length; k += 9, t += 6) {
          b.tri([v[k], v[k + 1], v[k + 2]], [v[k + 3], v[k + 4], v[k + 5]], [v[k + 6], v[k + 7], v[k + 8]], c, i, null,
            uv && [[uv[t], uv[t + 1], 0], [uv[t + 2], uv[t + 3], 0], [uv[t + 4], uv[t + 5], 0]], 1);
        }
      } else if (s.kind === 'mesh') {
        box(b, s.lo, s.hi, [c[0], c[1], c[2], 0.25], i);
      } else {
        const drawn = shape(b, scene, s, i, seg, c, tex >= 0);
        if (drawn === 'implicit') implicit++;
        if (drawn === 'surface') view.surfaceTriangles += s.surface.triangles;
      }
    });
    const notes = [];
    if (scene.truncated) notes.push('the first ' + shapes.length + ' of ' + scene.objects + ' objects are drawn');
    if (scene.simplified) {
      notes.push('meshes simplified: ' + scene.triangles_shown.toLocaleString() + ' of ' +
        scene.triangles.toLocaleString() + ' triangles drawn');
    }
    // An implicit surface without triangles (no sign change of f on the
    // server's grid, or too many triangles even at its coarsest) is drawn
    // as its box.
    if (implicit) notes.push(implicit + ' implicit surface' + (implicit > 1 ? 's' : '') + ' drawn as ' + (implicit > 1 ? 'their boxes' : 'its box'));
    if (spheres && seg < 16) notes.push('spheres and cones drawn with ' + seg + ' segments');
    view.baseNote = notes.join('; ');
    view.textured = textured;
    // opaque first (untextured, then by texture), then the see-through
    const order = [...groups.values()].sort((x, y) => (x.clear - y.clear) || (x.tex - y.tex));
    const all = new Float32Array(order.reduce((n, g) => n + g.b.data.length, 0));
    view.groups = [];
    let first = 0;
    for (const g of order) {
      const n = g.b.data.length / view.stride;
      view.groups.push({ first: first, count: n, clear: g.clear, tex: g.tex });
      all.set(g.b.data, first * view.stride);
      first += n;
    }
    view.opaque = view.groups.filter((g) => !g.clear).reduce((s, g) => s + g.count, 0);
    view.clear = first - view.opaque;
    view.triangles = first / 3;
    return all;
  }

  // ---- WebGL ----
  // Two programs on one vertex layout. The plain one (Lambert from two
  // directions on the vertex colour) draws every untextured surface, as
  // it always has. The texture one draws the groups of a texture: its
  // colour is the texture sampled at the renderer's (u, v) (uniform tk: 1
  // an image, 2 a checker; 0 while an image loads: the material's colour)
  // times the material colour, shown as the render shows a colour
  // (sRGB-encoded), under the same Lambert term. An image is sampled as
  // ggTextureBilinear and ggTextureNearest sample (include/ggrt/image.h):
  // the wrap mode first (repeat: u - floor(u) outside [0, 1]; clamp),
  // then texel (i, j) at d = ((w - 1) u, (h - 1) v), the four texels
  // blended in linear light (each decoded from the PNG's sRGB byte) and
  // clamped at 1. Texels are fetched with NEAREST filtering at their
  // centres, so WebGL's own filtering and wrap (and its need for
  // power-of-two sizes) play no part. It is compiled only for a scene
  // with textures (SwiftShader takes a second or more over it).
  const VS = 'attribute vec3 p; attribute vec3 n; attribute vec4 c; attribute float o;' +
    'uniform mat4 mvp; uniform float hl; varying vec3 vn; varying vec4 vc; varying float vh;' +
    'void main() { gl_Position = mvp * vec4(p, 1.0); vn = n; vc = c; vh = abs(o - hl) < 0.5 ? 1.0 : 0.0; }';
  const FS = 'precision mediump float; uniform vec3 L1; uniform vec3 L2; varying vec3 vn; varying vec4 vc; varying float vh;' +
    'void main() { vec3 n = normalize(vn);' +
    ' float d = 0.3 + 0.55 * abs(dot(n, L1)) + 0.25 * abs(dot(n, L2));' +
    ' vec3 col = vc.rgb * d; col = mix(col, vec3(0.0, 0.75, 0.9) * d, 0.45 * vh);' +
    ' gl_FragColor = vec4(col, max(vc.a, 0.6 * vh)); }';
  const VS_TEX = 'attribute vec3 p; attribute vec3 n; attribute vec4 c; attribute float o; attribute vec3 t; attribute float k;' +
    'uniform mat4 mvp; uniform float hl; varying vec3 vn; varying vec4 vc; varying float vh; varying vec3 vt; varying float vk;' +
    'void main() { gl_Position = mvp * vec4(p, 1.0); vn = n; vc = c; vh = abs(o - hl) < 0.5 ? 1.0 : 0.0; vt = t; vk = k; }';
  const FS_TEX = '#ifdef GL_FRAGMENT_PRECISION_HIGH\nprecision highp float;\n#else\nprecision mediump float;\n#endif\n' +
    'uniform vec3 L1; uniform vec3 L2; uniform float tk; uniform sampler2D tex; uniform vec2 ts; uniform float tw;' +
    ' uniform float tn; uniform float cn; uniform vec3 ca; uniform vec3 cb;' +
    'varying vec3 vn; varying vec4 vc; varying float vh; varying vec3 vt; varying float vk;' +
    'const float PI = 3.14159265358979;' +
    // u: a turn about an axis in [0, 1), 0 where it would round to 1
    'float turn(float y, float x) { float u = atan(y, x) / (2.0 * PI); if (u < 0.0) u += 1.0; return u >= 1.0 ? 0.0 : u; }' +
    'vec2 uvOf() {' +
    ' if (vk < 1.5) return vt.xy;' +
    ' if (vk < 2.5) return vec2(turn(vt.y, vt.x), acos(clamp(vt.z / max(length(vt), 1e-30), -1.0, 1.0)) / PI);' +
    ' return vec2(turn(vt.y, vt.x), clamp(vt.z, 0.0, 1.0)); }' +
    'float wrap(float x) { return tw > 0.5 ? clamp(x, 0.0, 1.0) : (x < 0.0 || x > 1.0 ? x - floor(x) : x); }' +
    'vec3 lin(vec3 s) { return mix(s / 12.92, pow((s + 0.055) / 1.055, vec3(2.4)), step(0.04045, s)); }' +
    'vec3 srgb(vec3 c) { return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c)); }' +
    'vec3 texel(float i, float j) { return lin(texture2D(tex, (vec2(i, j) + 0.5) / ts).rgb); }' +
    'vec3 sampled(vec2 uv) {' +
    ' if (tk > 1.5) { float s = floor((uv.x - floor(uv.x)) * cn) + floor((uv.y - floor(uv.y)) * cn);' +
    '  return mod(s, 2.0) < 0.5 ? ca : cb; }' +
    ' float di = (ts.x - 1.0) * wrap(uv.x), dj = (ts.y - 1.0) * wrap(uv.y);' +
    ' if (tn > 0.5) return min(texel(floor(di + 0.5), floor(dj + 0.5)), 1.0);' +
    ' float i = floor(di), j = floor(dj), a = di - i, b = dj - j;' +
    ' float i1 = min(i + 1.0, ts.x - 1.0), j1 = min(j + 1.0, ts.y - 1.0);' +
    ' return min(texel(i, j) * (1.0 - a) * (1.0 - b) + texel(i, j1) * (1.0 - a) * b +' +
    '  texel(i1, j) * a * (1.0 - b) + texel(i1, j1) * a * b, 1.0); }' +
    'void main() { vec3 n = normalize(vn);' +
    ' float d = 0.3 + 0.55 * abs(dot(n, L1)) + 0.25 * abs(dot(n, L2));' +
    ' vec3 base = tk > 0.5 ? srgb(clamp(sampled(uvOf()) * vc.rgb, 0.0, 1.0)) : 0.2 + 0.8 * vc.rgb;' +
    ' vec3 col = base * d; col = mix(col, vec3(0.0, 0.75, 0.9) * d, 0.45 * vh);' +
    ' gl_FragColor = vec4(col, max(vc.a, 0.6 * vh)); }';
  // The attributes at fixed locations, the same in both programs.
  const ATTRS = ['p', 'n', 'c', 'o', 't', 'k'];

  function program(gl, vs, fs) {
    const sh = (type, src) => {
      const s = gl.createShader(type);
      gl.shaderSource(s, src);
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error('3D view: ' + gl.getShaderInfoLog(s));
      return s;
    };
    const p = gl.createProgram();
    gl.attachShader(p, sh(gl.VERTEX_SHADER, vs));
    gl.attachShader(p, sh(gl.FRAGMENT_SHADER, fs));
    ATTRS.forEach((a, i) => gl.bindAttribLocation(p, i, a));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error('3D view: ' + gl.getProgramInfoLog(p));
    return p;
  }
  function glInit(canvas) {
    const gl = canvas.getContext('webgl', { antialias: true, preserveDrawingBuffer: true });
    if (!gl) return null;
    view.prog = program(gl, VS, FS);
    view.texProg = null; // made by loadTextures when the scene has textures
    view.buf = gl.createBuffer();
    return gl;
  }

  function upload(gl, data) {
    gl.bindBuffer(gl.ARRAY_BUFFER, view.buf);
    gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    const st = view.stride * 4;
    const at = (name, size, off) => {
      const l = ATTRS.indexOf(name);
      gl.enableVertexAttribArray(l);
      gl.vertexAttribPointer(l, size, gl.FLOAT, false, st, off * 4);
    };
    at('p', 3, 0); at('n', 3, 3); at('c', 4, 6); at('o', 1, 10);
    if (view.stride === 15) { at('t', 3, 11); at('k', 1, 14); }
  }

  // ---- textures ----
  // view.tex[i]: texture i as the shader takes it: {kind: 'checker', n, a,
  // b} at once; {kind: 'image', gl, size, wrap, filter} once its PNG
  // (/api/texture) is in; null while it loads or if it cannot be shown
  // (the note says why; the surface is drawn in its colour meanwhile).
  function loadTextures(gl, scene) {
    const app = window.ggrt, used = new Set(view.groups.map((g) => g.tex).filter((t) => t >= 0));
    view.tex = [];
    view.texNotes = [];
    view.texLoading = 0;
    if (used.size) view.texProg = program(gl, VS_TEX, FS_TEX);
    for (const i of used) {
      const d = scene.textures[i];
      if (d.kind === 'checker') {
        view.tex[i] = { kind: 'checker', n: d.n, a: d.a, b: d.b };
        continue;
      }
      view.tex[i] = null;
      view.texLoading++;
      app.api('/api/texture', { index: i }, 'blob')
        .then((r) => createImageBitmap(r.body, { premultiplyAlpha: 'none', colorSpaceConversion: 'none' }))
        .then((img) => {
          const max = gl.getParameter(gl.MAX_TEXTURE_SIZE);
          if (img.width > max || img.height > max) throw new Error(img.width + 'x' + img.height + ' is over this WebGL\'s ' + max);
          const t = gl.createTexture();
          gl.bindTexture(gl.TEXTURE_2D, t);
          gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
          gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
          gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
          gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGB, gl.RGB, gl.UNSIGNED_BYTE, img);
          // No mipmaps, no filtering, no wrap: the shader does those.
          gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
          gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
          gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
          gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
          view.tex[i] = { kind: 'image', gl: t, size: [img.width, img.height], wrap: d.wrap, filter: d.filter };
          if (img.close) img.close();
        })
        .catch((e) => { view.texNotes.push('texture ' + i + ' not shown: ' + e.message); })
        .finally(() => {
          view.texLoading--;
          if (!view.texLoading) $('box3d').dataset.textures = String(view.tex.filter((t) => t).length);
          draw();
        });
    }
    if (!view.texLoading) $('box3d').dataset.textures = String(view.tex.filter((t) => t).length);
  }
  // The filter the page's options ask for (their texture knob), else the
  // server's, else each texture's own: as the render of those options.
  function textureKnob() {
    const app = window.ggrt, re = /(?:^|[\s,;])texture\s*=\s*(scene|bilinear|nearest)\b/;
    const m = re.exec((app.state && app.state.a) || '') || re.exec(app.info.options || '');
    return m ? m[1] : 'scene';
  }
  // Bind texture group g's texture and set the texture program's uniforms.
  function useTexture(gl, g) {
    const u = (name) => gl.getUniformLocation(view.texProg, name), t = view.tex && view.tex[g.tex];
    if (!t) { gl.uniform1f(u('tk'), 0); return; }
    if (t.kind === 'checker') {
      gl.uniform1f(u('tk'), 2);
      gl.uniform1f(u('cn'), t.n);
      gl.uniform3fv(u('ca'), t.a);
      gl.uniform3fv(u('cb'), t.b);
      return;
    }
    const knob = textureKnob();
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, t.gl);
    gl.uniform1i(u('tex'), 0);
    gl.uniform1f(u('tk'), 1);
    gl.uniform2f(u('ts'), t.size[0], t.size[1]);
    gl.uniform1f(u('tw'), t.wrap === 'clamp' ? 1 : 0);
    gl.uniform1f(u('tn'), (knob === 'scene' ? t.filter : knob) === 'nearest' ? 1 : 0);
  }

  // ---- the orbit camera ----
  function basis(info) {
    const up = V.norm(info.camera.up);
    let e1 = Math.abs(up[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
    e1 = V.norm(V.sub(e1, V.mul(up, V.dot(e1, up))));
    view.up = up; view.e1 = e1; view.e2 = V.cross(up, e1);
  }
  function orbitFrom(eye) {
    const d = V.sub(eye, view.target), r = V.len(d) || 1;
    view.dist = r;
    view.pitch = Math.asin(Math.max(-1, Math.min(1, V.dot(d, view.up) / r)));
    view.yaw = Math.atan2(V.dot(d, view.e2), V.dot(d, view.e1));
  }
  function eyeOf() {
    const c = Math.cos(view.pitch);
    const d = V.add(V.add(V.mul(view.e1, c * Math.cos(view.yaw)), V.mul(view.e2, c * Math.sin(view.yaw))),
      V.mul(view.up, Math.sin(view.pitch)));
    return V.add(view.target, V.mul(d, view.dist));
  }
  const diagOf = (lo, hi) => V.len(V.sub(hi, lo)) || 1;

  // The segments of the selected rays, clipped to the scene's reach.
  function raySegments() {
    const app = window.ggrt, t = app && app.traces;
    const out = [];
    if (!t || !t.a) return out;
    const info = app.info, reach = 1.5 * diagOf(info.bounds.lo, info.bounds.hi);
    const sets = t.b ? [['a', t.a.json], ['b', t.b.json]] : [['a', t.a.json]];
    // Non-finite numbers may come as null or as "inf"/"nan" strings: such
    // a segment cannot be drawn and is left out.
    const ok = (p) => Array.isArray(p) && p.length === 3 && p.every((x) => typeof x === 'number' && isFinite(x));
    const push = (s) => { if (ok(s.a) && ok(s.b)) out.push(s); };
    for (const [side, j] of sets) {
      const walk = (n) => {
        const end = n.hit ? n.hit.point : V.add(n.origin, V.mul(V.norm(n.direction), reach));
        push({ side: side, id: n.id, kind: n.kind, a: n.origin, b: end, hit: !!n.hit, node: n });
        if (n.hit) {
          for (const L of n.hit.lights || []) {
            if (L.verdict === 'facing-away') continue;
            const tt = L.verdict === 'blocked' && typeof L.t_block === 'number' ? L.t_block : 1;
            push({ side: side, id: n.id, light: L.light, kind: 'shadow', verdict: L.verdict,
              a: L.origin, b: V.add(L.origin, V.mul(L.direction, tt)), node: n });
          }
        }
        for (const k of n.children) walk(k);
      };
      for (const r of j.roots) walk(r);
    }
    return out;
  }

  function preset(which) {
    const app = window.ggrt, info = app.info;
    basis(info);
    const lo = info.bounds.lo, hi = info.bounds.hi, diag = diagOf(lo, hi);
    const fwd = V.norm(V.sub(info.camera.at, info.camera.from));
    view.fov = 0;
    if (which === 'camera') {
      // Through the scene's camera: its eye, its aim and its field of
      // view (0.00001 degrees on acc-distant.nff), so that what the image
      // shows is in view.
      view.target = info.camera.at.slice();
      orbitFrom(info.camera.from);
      view.fov = info.camera.fov > 0 && info.camera.fov < 180 ? info.camera.fov : 0;
    } else if (which === 'rays') {
      // Frame the selected rays: their box, seen from the side of the camera.
      // Misses count with a stub as long as the box of the rest (they
      // would otherwise stretch it to the scene's reach).
      const segs = raySegments().filter((s) => s.kind !== 'shadow');
      if (!segs.length) return preset('camera');
      let a = [Infinity, Infinity, Infinity], b = [-Infinity, -Infinity, -Infinity];
      const grow = (p) => { a = a.map((v, i) => Math.min(v, p[i])); b = b.map((v, i) => Math.max(v, p[i])); };
      // The eye ray's start (the camera) is left out: the rays' box, not the
      // way from the camera to it.
      for (const s of segs) { if (s.kind !== 'eye') grow(s.a); if (s.hit) grow(s.b); }
      if (!isFinite(a[0])) return preset('camera');
      const stub = Math.max(diagOf(a, b), 0.15 * diag);
      for (const s of segs) if (!s.hit) grow(V.add(s.a, V.mul(V.norm(V.sub(s.b, s.a)), 0.5 * stub)));
      view.target = V.mul(V.add(a, b), 0.5);
      const r = Math.max(0.5 * diagOf(a, b), 0.1 * diag);
      const side = V.norm(V.add(V.mul(fwd, -1), V.mul(V.cross(fwd, view.up), 0.6)));
      orbitFrom(V.add(view.target, V.add(V.mul(side, 2.6 * r), V.mul(view.up, 0.8 * r))));
    } else {
      view.target = V.mul(V.add(lo, hi), 0.5);
      orbitFrom(V.add(view.target, V.mul(fwd, -diag)));
      if (which === 'top') view.pitch = Math.PI / 2 - 1e-3;
      else { view.pitch = 0; view.yaw += Math.PI / 2; }
      view.dist = diag * 1.2;
    }
    view.set = true;
    saveCam();
    draw();
  }

  // #cam=yaw,pitch,dist,tx,ty,tz[,fov] in the address, beside app.js's
  // keys; fov (degrees) when looking through the scene's camera. Only a
  // camera moved by hand (or by top, side, camera) is written: while the
  // view frames the selected rays the address has none, and a load, Back
  // or Forward frames its pixel's rays again. A camera move adjusts the
  // view: it replaces the history entry, never adds one (app.js, writeHash).
  function saveCam() {
    const p = new URLSearchParams(location.hash.slice(1));
    const r = (v) => Number(v.toPrecision(6));
    const v = [view.yaw, view.pitch, view.dist].concat(view.target);
    if (view.fov) v.push(view.fov);
    if (view.userMoved) p.set('cam', v.map(r).join(','));
    else p.delete('cam');
    const h = p.toString();
    history.replaceState(null, '', location.pathname + location.search + (h ? '#' + h : ''));
  }
  function loadCam() {
    const v = (new URLSearchParams(location.hash.slice(1)).get('cam') || '').split(',').map(Number);
    if ((v.length !== 6 && v.length !== 7) || !v.every(isFinite) || !(v[2] > 0)) return false;
    basis(window.ggrt.info);
    [view.yaw, view.pitch, view.dist] = v;
    view.target = v.slice(3, 6);
    view.fov = v.length === 7 && v[6] > 0 && v[6] < 180 ? v[6] : 0;
    view.set = true;
    return true;
  }

  // The vertical field of view (radians): 45 degrees, or the scene
  // camera's, widened so that its whole image fits the canvas.
  function fovY(info, Wc, Hc) {
    if (!view.fov) return 45 * Math.PI / 180;
    const tx = Math.tan(view.fov * Math.PI / 360), ty = tx * info.height / info.width;
    return 2 * Math.atan(Math.max(ty, tx * Hc / Wc));
  }
  // The near and far planes of the shaded scene: [near, far] (those of
  // the rays, lights and frustum drawn over it) narrowed to the scene's
  // box as seen from eye, so that a camera far from a small scene (3e7
  // from unit spheres) keeps the precision of its depth buffer.
  function sceneRange(eye, diag, lo, hi, near, far) {
    const dir = V.norm(V.sub(view.target, eye));
    let zmin = Infinity, zmax = -Infinity;
    for (let i = 0; i < 8; i++) {
      const c = [i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]];
      const z = V.dot(V.sub(c, eye), dir);
      zmin = Math.min(zmin, z); zmax = Math.max(zmax, z);
    }
    const pad = 0.05 * diag, n = Math.max(near, zmin - pad), f = Math.min(far, zmax + pad);
    return f > n ? [n, f] : [near, far];
  }

  // ---- drawing ----
  function project(p) {
    const c = M.apply(view.mvp, p);
    return c;
  }
  // A segment in clip space cut at the near plane (z > -w), then on screen,
  // then clipped (Liang-Barsky) to a box a margin larger than the canvas:
  // a ray that runs far off screen would otherwise reach the 2D canvas
  // with coordinates of 1e5 px and more, which it strokes (and dashes) for
  // seconds. The part on screen is the same; t0 is the fraction cut from
  // the start, for the dashes' phase.
  const CLIP_MARGIN = 64;
  function screenSeg(a, b, Wc, Hc) {
    let p = project(a), q = project(b);
    const da = p[2] + p[3], db = q[2] + q[3];
    if (da < 0 && db < 0) return null;
    const cut = (u, v, du, dv) => { const t = du / (du - dv); return u.map((x, i) => x + (v[i] - x) * t); };
    if (da < 0) p = cut(p, q, da, db);
    if (db < 0) q = cut(q, p, db, da);
    const s = (c) => [(c[0] / c[3] * 0.5 + 0.5) * Wc, (0.5 - c[1] / c[3] * 0.5) * Hc];
    if (!(p[3] > 0) || !(q[3] > 0)) return null;
    const P = s(p), Q = s(q);
    if (!P.concat(Q).every(isFinite)) return null;
    const dx = Q[0] - P[0], dy = Q[1] - P[1];
    let t0 = 0, t1 = 1;
    const edge = (num, den) => { // keep the part where num + t * den >= 0
      if (den === 0) return num >= 0;
      const t = -num / den;
      if (den > 0) { if (t > t0) t0 = t; } else if (t < t1) t1 = t;
      return t0 <= t1;
    };
    const m = CLIP_MARGIN;
    if (!(edge(P[0] + m, dx) && edge(Wc + m - P[0], -dx) && edge(P[1] + m, dy) && edge(Hc + m - P[1], -dy))) return null;
    const r = [[P[0] + t0 * dx, P[1] + t0 * dy], [P[0] + t1 * dx, P[1] + t1 * dy]];
    r.skip = t0 * Math.hypot(dx, dy); // the length cut from the start, in px
    return r;
  }

  function draw() {
    const app = window.ggrt;
    if (!app || !app.info || !view.gl) return;
    const c = $('gl3d'), o = $('ov3d'), gl = view.gl;
    const Wc = c.clientWidth || c.width, Hc = c.clientHeight || c.height;
    if (c.width !== Wc || c.height !== Hc) { c.width = Wc; c.height = Hc; o.width = Wc; o.height = Hc; }
    if (!view.set && loadCam()) view.userMoved = true;
    if (!view.set) return preset(app.traces && app.traces.a ? 'rays' : 'camera');
    const info = app.info, eye = eyeOf(), diag = diagOf(info.bounds.lo, info.bounds.hi);
    const far = V.len(V.sub(eye, view.target)) + 4 * diag, near = Math.max(far * 1e-5, view.dist * 1e-3);
    let up = view.up;
    if (Math.abs(V.dot(V.norm(V.sub(view.target, eye)), up)) > 0.999) up = view.e2;
    const look = M.lookAt(eye, view.target, up), fovy = fovY(info, Wc, Hc);
    view.mvp = M.mul(M.perspective(fovy, Wc / Hc, near, far), look);
    const [gn, gf] = sceneRange(eye, diag, info.bounds.lo, info.bounds.hi, near, far);
    const glMvp = new Float32Array(M.mul(M.perspective(fovy, Wc / Hc, gn, gf), look));
    gl.viewport(0, 0, Wc, Hc);
    gl.clearColor(0.97, 0.97, 0.955, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    const use = (p) => {
      gl.useProgram(p);
      gl.uniformMatrix4fv(gl.getUniformLocation(p, 'mvp'), false, glMvp);
      gl.uniform1f(gl.getUniformLocation(p, 'hl'), view.hlObject);
      gl.uniform3fv(gl.getUniformLocation(p, 'L1'), V.norm(V.sub(eye, view.target)));
      gl.uniform3fv(gl.getUniformLocation(p, 'L2'), view.up);
    };
    gl.enable(gl.DEPTH_TEST);
    gl.disable(gl.BLEND);
    gl.depthMask(true);
    // The opaque groups, then the see-through ones blended over them;
    // each untextured one with the plain program, each texture's with
    // the texture program.
    let cur = null;
    for (const g of view.groups) {
      if (!g.count) continue;
      if (g.clear) {
        gl.enable(gl.BLEND);
        gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
        gl.depthMask(false);
      }
      const p = g.tex >= 0 && view.texProg ? view.texProg : view.prog;
      if (p !== cur) { use(p); cur = p; }
      if (p === view.texProg) useTexture(gl, g);
      gl.drawArrays(gl.TRIANGLES, g.first, g.count);
    }
    gl.depthMask(true);
    overlay(o.getContext('2d'), Wc, Hc, info, diag);
  }

  function overlay(g, Wc, Hc, info, diag) {
    g.clearRect(0, 0, Wc, Hc);
    const line = (a, b, colour, w, dash) => {
      const s = screenSeg(a, b, Wc, Hc);
      if (!s) return null;
      g.beginPath();
      g.setLineDash(dash || []);
      // The dashes keep their phase where the start was clipped away.
      const period = dash ? dash.reduce((x, y) => x + y, 0) : 0;
      g.lineDashOffset = period ? s.skip % period : 0;
      g.strokeStyle = colour;
      g.lineWidth = w;
      g.moveTo(s[0][0], s[0][1]);
      g.lineTo(s[1][0], s[1][1]);
      g.stroke();
      return s;
    };
    const dot = (p, colour, r) => {
      const c = project(p);
      if (!(c[3] > 0) || c[2] < -c[3]) return null;
      const s = [(c[0] / c[3] * 0.5 + 0.5) * Wc, (0.5 - c[1] / c[3] * 0.5) * Hc];
      if (!(Math.abs(s[0] - Wc / 2) < Wc / 2 + CLIP_MARGIN && Math.abs(s[1] - Hc / 2) < Hc / 2 + CLIP_MARGIN)) return null;
      g.beginPath();
      g.fillStyle = colour;
      g.arc(s[0], s[1], r, 0, 2 * Math.PI);
      g.fill();
      return s;
    };
    frustum(line, info, diag);
    g.font = '11px system-ui, sans-serif';
    const lights = (window.ggrt.scene && window.ggrt.scene.lights) || [];
    lights.forEach((L, i) => {
      const s = dot(L.position, '#f59e0b', 6);
      if (s) {
        g.strokeStyle = '#7c4a03'; g.lineWidth = 1; g.setLineDash([]);
        g.beginPath(); g.arc(s[0], s[1], 6, 0, 2 * Math.PI); g.stroke();
        g.fillStyle = '#7c4a03';
        g.fillText('light ' + i, s[0] + 8, s[1] - 6);
      }
    });
    view.segs = [];
    const hl = view.hl;
    for (const s of raySegments()) {
      const sel = s.side === 'a' && s.id === hl;
      const dash = s.side === 'b' ? [6, 4] : null;
      let sc;
      if (s.kind === 'shadow') {
        sc = line(s.a, s.b, LIGHT[s.verdict] || '#f59e0b', sel ? 2.2 : 1.1, [5, 3]);
        if (s.verdict === 'blocked') dot(s.b, '#dc2626', 3);
      } else {
        if (sel) line(s.a, s.b, 'rgba(0, 200, 230, 0.55)', 9);
        sc = line(s.a, s.b, KIND[s.kind], sel ? 3.5 : 2, dash);
        if (s.hit) dot(s.b, KIND[s.kind], sel ? 4.5 : 3);
      }
      if (sc) view.segs.push({ s: sc, id: s.id, side: s.side, kind: s.kind });
    }
    g.setLineDash([]);
    g.lineDashOffset = 0;
    $('note3d').textContent = [view.baseNote].concat(view.texNotes || []).filter((x) => x).join('; ');
  }

  // The camera: its eye, the image's four corner rays and the image plane.
  function frustum(line, info, diag) {
    const cam = info.camera, W = info.width, H = info.height;
    const f = V.norm(V.sub(cam.at, cam.from)), r = V.norm(V.cross(f, cam.up)), u = V.cross(r, f);
    const tx = Math.tan(cam.fov * Math.PI / 360), ty = tx * H / W;
    const d = Math.min(V.len(V.sub(cam.at, cam.from)), 0.35 * diag);
    const corner = (sx, sy) => V.add(cam.from, V.mul(V.add(f, V.add(V.mul(r, sx * tx), V.mul(u, sy * ty))), d));
    const cs = [corner(-1, 1), corner(1, 1), corner(1, -1), corner(-1, -1)];
    for (let i = 0; i < 4; i++) {
      line(cam.from, cs[i], 'rgba(107, 114, 128, 0.7)', 1);
      line(cs[i], cs[(i + 1) % 4], 'rgba(107, 114, 128, 0.9)', 1);
    }
    line(cs[0], cs[1], '#4b5563', 2); // the image's top edge
  }

  // ---- linking: the node under the mouse, a click on a segment ----
  function highlight(id) {
    const t = window.ggrt && window.ggrt.traces;
    view.hl = id;
    let obj = -1;
    if (t && t.a && id >= 0) {
      const find = (n) => n.id === id ? n : n.children.map(find).find((x) => x) || null;
      for (const r of t.a.json.roots) {
        const n = find(r);
        if (n) { obj = n.hit ? n.hit.object : -1; break; }
      }
    }
    view.hlObject = obj;
    draw();
    return obj;
  }
  view.highlight = highlight;
  view.draw = draw;
  view.preset = preset;

  function pick(x, y) {
    let best = null, bd = 8;
    for (const s of view.segs) {
      const [[x0, y0], [x1, y1]] = s.s, dx = x1 - x0, dy = y1 - y0;
      const t = Math.max(0, Math.min(1, ((x - x0) * dx + (y - y0) * dy) / (dx * dx + dy * dy || 1)));
      const d = Math.hypot(x - x0 - t * dx, y - y0 - t * dy);
      if (d < bd || (d === bd && s.kind !== 'shadow')) { bd = d; best = s; }
    }
    return best;
  }

  view.pick = pick;

  function wire() {
    const c = $('ov3d');
    let drag = null, moved = false;
    c.addEventListener('pointerdown', (e) => {
      drag = [e.clientX, e.clientY, e.shiftKey]; moved = false; c.setPointerCapture(e.pointerId);
    });
    c.addEventListener('pointerup', (e) => {
      const was = drag;
      drag = null;
      if (was && moved) { view.userMoved = true; saveCam(); return; }
      const r = c.getBoundingClientRect(), s = pick(e.clientX - r.left, e.clientY - r.top);
      if (s && window.ggrtLinks) window.ggrtLinks.selectNode(s.side, s.id, 'view');
    });
    c.addEventListener('pointermove', (e) => {
      if (!drag) {
        const r = c.getBoundingClientRect(), s = pick(e.clientX - r.left, e.clientY - r.top);
        c.style.cursor = s ? 'pointer' : 'grab';
        c.title = s ? 'ray #' + s.id + ' (' + s.kind + '): click to select it in the tree' : '';
        return;
      }
      const dx = e.clientX - drag[0], dy = e.clientY - drag[1];
      if (Math.abs(dx) + Math.abs(dy) > 2) moved = true;
      if (drag[2]) { // shift-drag pans
        const eye = eyeOf(), f = V.norm(V.sub(view.target, eye)), r = V.norm(V.cross(f, view.up)), u = V.cross(r, f);
        const k = view.dist * 0.0015;
        view.target = V.add(view.target, V.add(V.mul(r, -dx * k), V.mul(u, dy * k)));
      } else {
        view.yaw -= dx * 0.01;
        view.pitch = Math.max(-1.55, Math.min(1.55, view.pitch + dy * 0.01));
      }
      drag = [e.clientX, e.clientY, drag[2]];
      draw();
    });
    c.addEventListener('wheel', (e) => {
      e.preventDefault();
      view.dist *= Math.exp(e.deltaY * 0.001);
      view.userMoved = true;
      saveCam();
      draw();
    }, { passive: false });
    for (const b of document.querySelectorAll('#box3d [data-view]')) {
      b.addEventListener('click', () => { view.userMoved = b.dataset.view !== 'rays'; preset(b.dataset.view); });
    }
    window.addEventListener('resize', draw);
  }

  // Started by app.js once /api/info and /api/scene are in (ggrt:ready).
  document.addEventListener('ggrt:ready', () => {
    const app = window.ggrt;
    try {
      view.gl = glInit($('gl3d'));
    } catch (e) {
      view.gl = null;
      $('note3d').textContent = e.message;
    }
    if (!view.gl) {
      $('note3d').textContent = 'this browser gives no WebGL: the 3D view is off';
      return;
    }
    upload(view.gl, build(app.scene));
    loadTextures(view.gl, app.scene);
    view.built = true;
    $('box3d').dataset.triangles = String(view.triangles);
    $('box3d').dataset.meshTriangles = String(view.meshTriangles);
    $('box3d').dataset.surfaceTriangles = String(view.surfaceTriangles);
    wire();
    draw();
  });
  // The address changed in the open page (Back, Forward, a link): a
  // camera in it is taken as one set by hand; without one the view frames
  // the pixel's rays (ggrt:pixel, once its tree is shown), as it did when
  // that address was written.
  document.addEventListener('ggrt:hash', () => {
    if (!view.gl) return;
    if (loadCam()) {
      view.userMoved = true;
      draw();
    } else {
      view.userMoved = false;
      if (!window.ggrt.state.px) preset('camera');
    }
  });
  // Options rendered: their texture knob may pick another filter.
  document.addEventListener('ggrt:image', () => { if (view.gl && view.textured) draw(); });
  document.addEventListener('ggrt:pixel', () => {
    if (!view.gl) return;
    // A new pixel's rays are framed unless the camera was moved by hand
    // (or came from the address); the "rays" button frames them again.
    if (!view.set && loadCam()) view.userMoved = true;
    view.hl = -1;
    view.hlObject = -1;
    // After the tree is on screen: the tree comes first.
    requestAnimationFrame(() => setTimeout(() => (view.userMoved ? draw() : preset('rays')), 0));
  });
})();
