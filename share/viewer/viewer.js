// kelp-viewer's page: the pMarineViewer role in a browser. Shipped with kelp; nothing is
// fetched from elsewhere. The server streams JSON (Server-Sent Events, /events): a snapshot
// first ("full":1), then the changes since the one before (see include/kelp/viewer.h).
// window.kelpViewer is the page's own state (tests read it).
'use strict';
(function () {
  const S = window.kelpViewer = {
    cfg: null, seq: 0, now: 0, rate: 1, nowAt: 0, vehicles: {}, artifacts: {}, casts: {}, selected: '',
    frames: 0, messages: 0, fps: 0, drawMs: 0, replay: null, connected: false, pressed: [],
    view: { cx: 0, cy: 0, scale: 2, fitted: false, auto: true } // scale: pixels per metre; auto: keep every vehicle in view
  };
  const qs = new URLSearchParams(location.search);
  const tokenQ = qs.get('token') ? 'token=' + encodeURIComponent(qs.get('token')) : '';
  const withToken = (u) => tokenQ ? u + (u.indexOf('?') < 0 ? '?' : '&') + tokenQ : u;
  const $ = (id) => document.getElementById(id);
  const canvas = $('map'), ctx = canvas.getContext('2d');
  let bgImage = null, bgUrl = '';

  // ---------------------------------------------------------------- colours (MOOS names -> CSS)
  const colourCache = {};
  function colour(name, dflt) {
    if (!name) return dflt;
    let c = colourCache[name];
    if (c !== undefined) return c || dflt;
    let n = String(name).trim().toLowerCase();
    if (n === 'off' || n === 'invisible' || n === 'empty') c = 'transparent';
    else if (/^hex:[0-9a-f]{6}$/.test(n)) c = '#' + n.slice(4);
    else if (/^0x[0-9a-f]{6}$/.test(n)) c = '#' + n.slice(2);
    else if (/^[0-9.]+:[0-9.]+:[0-9.]+$/.test(n)) { // "r:g:b" in 0..1
      const p = n.split(':').map(Number);
      c = 'rgb(' + p.map((v) => Math.round(Math.min(1, v) * 255)).join(',') + ')';
    } else {
      n = n.replace(/[_ ]/g, '');
      if (n === 'darkblue2') n = 'darkblue';
      c = (window.CSS && CSS.supports('color', n)) ? n : '';
    }
    colourCache[name] = c;
    return c || dflt;
  }

  // ---------------------------------------------------------------- geodesy (UTM as MOOS-IvP 24.8, kelp/geo.h)
  const D2R = Math.PI / 180;
  function utm(lat, lon, lonc) { // Snyder's series (USGS Bulletin 1532), no false origin
    const e2 = 0.00669438, e4 = e2 * e2, e6 = e4 * e2, ep2 = e2 / (1 - e2), a = 6378137, k0 = 0.9996;
    const p = lat * D2R, s = Math.sin(p), c = Math.cos(p), t = Math.tan(p);
    const N = a / Math.sqrt(1 - e2 * s * s), T = t * t, C = ep2 * c * c, A = c * (lon - lonc) * D2R;
    const M = a * ((1 - e2 / 4 - 3 * e4 / 64 - 5 * e6 / 256) * p - (3 * e2 / 8 + 3 * e4 / 32 + 45 * e6 / 1024) * Math.sin(2 * p) +
                   (15 * e4 / 256 + 45 * e6 / 1024) * Math.sin(4 * p) - (35 * e6 / 3072) * Math.sin(6 * p));
    return [k0 * N * (A + (1 - T + C) * A ** 3 / 6 + (5 - 18 * T + T * T + 72 * C - 58 * ep2) * A ** 5 / 120),
            k0 * (M + N * t * (A * A / 2 + (5 - T + 9 * C + 4 * C * C) * A ** 4 / 24 + (61 - 58 * T + T * T + 600 * C - 330 * ep2) * A ** 6 / 720))];
  }
  function gridLatLon(c, x, y) {
    const sy = y / c.R, sx = x / (c.R * Math.cos(c.lat0 * D2R));
    if (Math.abs(sy) > 1 || Math.abs(sx) > 1) return null;
    return [c.lat0 + Math.asin(sy) / D2R, c.lon0 + Math.asin(sx) / D2R];
  }
  function toLatLon(x, y) { // MOOS's inverse: the grid's answer corrected until within 1 m
    const c = S.cfg;
    if (!c || !c.datum) return null;
    let gx = x, gy = y, err = Infinity;
    for (let i = 0; i < 16 && err > 1; i++) {
      const ll = gridLatLon(c, gx, gy);
      if (!ll) return null;
      const [e, n] = utm(ll[0], ll[1], c.lonc), dx = e - c.e0 - x, dy = n - c.n0 - y;
      gx -= dx; gy -= dy; err = Math.hypot(dx, dy);
    }
    return err > 1 ? null : gridLatLon(c, gx, gy);
  }
  function toLocal(lat, lon) {
    const c = S.cfg, [e, n] = utm(lat, lon, c.lonc);
    return [e - c.e0, n - c.n0];
  }

  // ---------------------------------------------------------------- the model from the stream
  function modelNow() { return S.now + (performance.now() - S.nowAt) / 1000 * S.rate; }

  function apply(m) {
    S.messages++;
    if (m.full) {
      S.vehicles = {}; S.artifacts = {}; S.casts = {};
      if (m.cfg) setConfig(m.cfg);
    }
    S.seq = m.seq; S.now = m.now; S.rate = m.rate; S.nowAt = performance.now();
    const cap = (S.cfg && S.cfg.trails) || 100;
    for (const v of m.veh) {
      if (v.gone) { delete S.vehicles[v.name]; continue; }
      const old = S.vehicles[v.name];
      const trail = m.full || !old ? [] : old.trail;
      for (const p of v.trail) trail.push(p);
      if (trail.length > cap) trail.splice(0, trail.length - cap);
      v.trail = trail;
      S.vehicles[v.name] = v;
    }
    for (const a of m.art) {
      const key = a.kind + ':' + a.label;
      if (a.gone) delete S.artifacts[key]; else S.artifacts[key] = a;
    }
    for (const c of (m.cast || [])) S.casts[c.node + '/' + c.proc] = c;
    if (m.cast && m.cast.length) castsDirty = true;
    if (!S.view.fitted && Object.keys(S.vehicles).length) { fit(); S.view.fitted = true; }
    updateList();
    updatePanel();
  }

  function setConfig(c) {
    S.cfg = c;
    const bar = $('buttons'), menu = $('actions');
    bar.textContent = '';
    menu.length = 1;
    for (const cmd of c.cmds) {
      if (cmd.kind === 'button') {
        const b = document.createElement('button');
        b.id = 'cmd-' + cmd.i; b.textContent = cmd.label; b.title = cmd.pokes.join('  ');
        if (cmd.color) b.style.background = colour(cmd.color, '');
        b.addEventListener('click', () => press(cmd.i, cmd.label));
        bar.appendChild(b);
      } else {
        const o = document.createElement('option');
        o.value = String(cmd.i); o.textContent = cmd.label + (cmd.key ? '  <' + cmd.key + '>' : '');
        o.title = cmd.key ? 'posts every action with menu_key ' + cmd.key : cmd.pokes.join('  ');
        menu.appendChild(o);
        if (cmd.sep) { const s = document.createElement('option'); s.disabled = true; s.textContent = '──────'; menu.appendChild(s); }
      }
    }
    menu.hidden = menu.length <= 1;
    if (c.image && c.image.url !== bgUrl && c.datum) {
      bgUrl = c.image.url;
      const img = new Image();
      img.onload = () => { bgImage = img; };
      img.src = withToken(c.image.url);
    }
  }

  function press(i, label) {
    S.pressed.push(label);
    fetch(withToken('/cmd?i=' + i), { method: 'POST', headers: { 'X-Kelp': '1' } })
      .then((r) => { status(r.ok ? 'sent: ' + label : 'refused: ' + label); })
      .catch(() => status('not sent: ' + label));
  }
  function replayOp(op, v) {
    fetch(withToken('/replay?op=' + op + (v !== undefined ? '&v=' + v : '')), { method: 'POST', headers: { 'X-Kelp': '1' } });
  }

  let statusText = '';
  function status(t) { statusText = t; }

  function connect() {
    const es = new EventSource(withToken('/events'));
    es.onopen = () => { S.connected = true; };
    es.onmessage = (e) => { try { apply(JSON.parse(e.data)); } catch (err) { console.error(err); } };
    es.addEventListener('replay', (e) => {
      S.replay = JSON.parse(e.data);
      document.body.classList.add('replaying');
      $('replay').hidden = false;
      const r = S.replay, span = Math.max(1e-9, r.t1 - r.t0);
      if (!sliderHeld) $('slider').value = String(Math.round((r.t - r.t0) / span * 1000));
      $('rtime').textContent = (r.t - r.t0).toFixed(1) + ' / ' + span.toFixed(1) + ' s';
      $('play').textContent = r.playing ? 'Pause' : 'Play';
      if (document.activeElement !== $('speed')) $('speed').value = String(r.speed);
    });
    es.onerror = () => { S.connected = false; };
  }

  // ---------------------------------------------------------------- view: pan, zoom, centre
  function toScreen(x, y) {
    const v = S.view;
    return [canvas.width / 2 + (x - v.cx) * v.scale, canvas.height / 2 - (y - v.cy) * v.scale];
  }
  function toWorld(px, py) {
    const v = S.view;
    return [v.cx + (px - canvas.width / 2) / v.scale, v.cy - (py - canvas.height / 2) / v.scale];
  }
  function fit() {
    const vs = Object.values(S.vehicles);
    if (!vs.length) return;
    let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
    for (const v of vs) { x0 = Math.min(x0, v.x); x1 = Math.max(x1, v.x); y0 = Math.min(y0, v.y); y1 = Math.max(y1, v.y); }
    const w = Math.max(100, x1 - x0), h = Math.max(100, y1 - y0);
    S.view.cx = (x0 + x1) / 2; S.view.cy = (y0 + y1) / 2;
    S.view.scale = Math.min(canvas.width / (w * 1.6), canvas.height / (h * 1.6));
  }
  function centre() {
    const v = S.vehicles[S.selected];
    if (v) { S.view.cx = v.x; S.view.cy = v.y; }
  }
  function select(name) {
    S.selected = name;
    $('vehicle-list').value = name;
    if (Object.values(S.casts).some((c) => c.node === name)) { $('cast-node').value = name; castsDirty = true; }
    updatePanel();
  }

  // ---------------------------------------------------------------- AppCasts (the APPCAST strings, kelp/appcast.h)
  let castsDirty = false, castNodesKey = '';
  function parseCast(text) {
    const out = {};
    for (const pair of text.split('!@#')) {
      const i = pair.indexOf('=');
      if (i > 0 && !(pair.slice(0, i) in out)) out[pair.slice(0, i)] = pair.slice(i + 1);
    }
    return out;
  }
  function updateCasts() {
    castsDirty = false;
    const sel = $('cast-node'), nodes = [...new Set(Object.values(S.casts).map((c) => c.node))].sort();
    if (nodes.join(',') !== castNodesKey) {
      castNodesKey = nodes.join(',');
      const keep = sel.value;
      sel.length = 0;
      for (const n of nodes) { const o = document.createElement('option'); o.value = n; o.textContent = n || '(no node)'; sel.appendChild(o); }
      sel.value = nodes.includes(keep) ? keep : (nodes.includes(S.selected) ? S.selected : (nodes[0] || ''));
    }
    const box = $('casts'), open = new Set([...box.querySelectorAll('details[open]')].map((d) => d.dataset.proc));
    box.textContent = '';
    const casts = Object.values(S.casts).filter((c) => c.node === sel.value).sort((a, b) => a.proc.localeCompare(b.proc));
    for (const c of casts) {
      const f = parseCast(c.text), cfg = f.config_warnings ? f.config_warnings.split('!@').filter(Boolean) : [];
      const run = f.run_warnings ? f.run_warnings.split('!@').filter(Boolean) : [];
      const d = document.createElement('details'), sm = document.createElement('summary'), pre = document.createElement('pre');
      d.dataset.proc = c.proc; d.open = open.has(c.proc);
      sm.textContent = c.proc + '  iter ' + (f.iter || '?') + (cfg.length ? '  cfg ' + cfg.length : '') +
        (f.run_warning_total && f.run_warning_total !== '0' ? '  run ' + f.run_warning_total : '');
      if (cfg.length || run.length) sm.className = 'warn';
      pre.textContent = [...cfg.map((w) => 'config warning: ' + w), ...run.map((w) => 'run warning: ' + w),
        (f.messages || '').split('!@').join('\n'), ...(f.events ? f.events.split('!@').map((e) => 'event ' + e) : [])].join('\n');
      d.appendChild(sm); d.appendChild(pre); box.appendChild(d);
    }
  }
  $('cast-node').addEventListener('change', () => { castsDirty = true; });

  let drag = null, sliderHeld = false;
  canvas.addEventListener('mousedown', (e) => { drag = { x: e.offsetX, y: e.offsetY, moved: false }; });
  window.addEventListener('mouseup', (e) => {
    if (drag && !drag.moved && e.target === canvas) pick(e.offsetX, e.offsetY);
    drag = null;
  });
  canvas.addEventListener('mousemove', (e) => {
    const [x, y] = toWorld(e.offsetX, e.offsetY);
    const ll = toLatLon(x, y);
    $('readout').textContent = 'x=' + x.toFixed(1) + ' y=' + y.toFixed(1) +
      (ll ? '   lat=' + ll[0].toFixed(6) + ' lon=' + ll[1].toFixed(6) : '   (no datum)');
    if (!drag) return;
    const dx = e.offsetX - drag.x, dy = e.offsetY - drag.y;
    if (Math.abs(dx) + Math.abs(dy) > 2) drag.moved = true;
    S.view.cx -= dx / S.view.scale; S.view.cy += dy / S.view.scale;
    drag.x = e.offsetX; drag.y = e.offsetY;
    if (drag.moved) S.view.auto = false;
    $('follow').checked = false;
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    S.view.auto = false;
    const [wx, wy] = toWorld(e.offsetX, e.offsetY);
    const f = Math.exp(-e.deltaY * 0.0015);
    S.view.scale = Math.min(500, Math.max(0.001, S.view.scale * f));
    const [nx, ny] = toWorld(e.offsetX, e.offsetY); // keep the point under the pointer in place
    S.view.cx += wx - nx; S.view.cy += wy - ny;
  }, { passive: false });
  function pick(px, py) {
    let best = '', bd = 15 * 15;
    for (const v of Object.values(S.vehicles)) {
      const [sx, sy] = toScreen(v.x, v.y), d = (sx - px) ** 2 + (sy - py) ** 2;
      if (d < bd) { bd = d; best = v.name; }
    }
    if (best) select(best);
  }
  $('centre').addEventListener('click', () => { S.view.auto = false; centre(); });
  $('fit').addEventListener('click', () => { S.view.auto = true; fit(); });
  $('vehicle-list').addEventListener('change', (e) => { select(e.target.value); S.view.auto = false; centre(); });
  $('actions').addEventListener('change', (e) => {
    const i = e.target.value;
    if (i !== '') press(Number(i), e.target.selectedOptions[0].textContent);
    e.target.value = '';
  });
  window.addEventListener('keydown', (e) => {
    if (e.target.tagName === 'INPUT' || e.target.tagName === 'SELECT') return;
    if (e.key === 'c') centre();
    else if (e.key === 'f') { S.view.auto = true; fit(); }
  });
  $('play').addEventListener('click', () => replayOp(S.replay && S.replay.playing ? 'pause' : 'play'));
  $('speed').addEventListener('change', (e) => replayOp('speed', e.target.value));
  $('slider').addEventListener('input', () => { sliderHeld = true; });
  $('slider').addEventListener('change', (e) => {
    sliderHeld = false;
    if (S.replay) replayOp('seek', (Number(e.target.value) / 1000 * (S.replay.t1 - S.replay.t0)).toFixed(3));
  });

  let listKey = '';
  function updateList() {
    const names = Object.keys(S.vehicles).sort();
    const key = names.join(',');
    if (key === listKey) return;
    listKey = key;
    const sel = $('vehicle-list');
    sel.length = 1;
    if (names.length <= 2000) for (const n of names) { const o = document.createElement('option'); o.value = n; o.textContent = n; sel.appendChild(o); }
    sel.value = S.selected;
  }
  const FIELDS = [['type', 'TYPE'], ['mode', 'MODE'], ['x', 'X (m)'], ['y', 'Y (m)'], ['lat', 'LAT'], ['lon', 'LON'],
    ['hdg', 'HDG (deg)'], ['spd', 'SPD (m/s)'], ['dep', 'DEPTH (m)'], ['len', 'LENGTH (m)'], ['group', 'GROUP'],
    ['color', 'COLOR'], ['allstop', 'ALLSTOP'], ['rtime', 'TIME'], ['n', 'reports'], ['stale', 'stale']];
  function updatePanel() {
    const v = S.vehicles[S.selected];
    $('sel-name').textContent = v ? v.name : 'no vehicle selected';
    const t = $('sel-fields');
    t.textContent = '';
    if (!v) return;
    for (const [k, label] of FIELDS) {
      if (v[k] === undefined || v[k] === '') continue;
      const tr = t.insertRow();
      tr.insertCell().textContent = label;
      tr.insertCell().textContent = k === 'stale' ? (v.stale ? 'yes' : 'no') : String(v[k]);
    }
    const tr = t.insertRow();
    tr.insertCell().textContent = 'age (s)';
    tr.insertCell().textContent = (modelNow() - v.t).toFixed(1);
  }

  // ---------------------------------------------------------------- drawing
  function niceStep(px) { // metres per grid line for about px pixels
    const m = px / S.view.scale, p = Math.pow(10, Math.floor(Math.log10(m))), r = m / p;
    return (r < 2 ? 2 : r < 5 ? 5 : 10) * p;
  }
  function drawGrid() {
    const step = niceStep(90), [x0, y1] = toWorld(0, 0), [x1, y0] = toWorld(canvas.width, canvas.height);
    ctx.strokeStyle = 'rgba(255,255,255,0.09)'; ctx.fillStyle = 'rgba(255,255,255,0.35)'; ctx.lineWidth = 1;
    ctx.font = '10px sans-serif';
    ctx.beginPath();
    for (let x = Math.ceil(x0 / step) * step; x <= x1; x += step) { const [sx] = toScreen(x, 0); ctx.moveTo(sx, 0); ctx.lineTo(sx, canvas.height); ctx.fillText(String(+x.toFixed(3)), sx + 2, canvas.height - 3); }
    for (let y = Math.ceil(y0 / step) * step; y <= y1; y += step) { const [, sy] = toScreen(0, y); ctx.moveTo(0, sy); ctx.lineTo(canvas.width, sy); ctx.fillText(String(+y.toFixed(3)), 2, sy - 2); }
    ctx.stroke();
    const [dx, dy] = toScreen(0, 0); // the datum
    ctx.strokeStyle = 'rgba(255,255,255,0.5)';
    ctx.beginPath(); ctx.moveTo(dx - 8, dy); ctx.lineTo(dx + 8, dy); ctx.moveTo(dx, dy - 8); ctx.lineTo(dx, dy + 8); ctx.stroke();
  }
  function drawImage() {
    const c = S.cfg;
    if (!bgImage || !c || !c.image || !c.datum) return;
    const [xw, yn] = toLocal(c.image.n, c.image.w), [xe, ys] = toLocal(c.image.s, c.image.e);
    const [sx0, sy0] = toScreen(xw, yn), [sx1, sy1] = toScreen(xe, ys);
    ctx.drawImage(bgImage, sx0, sy0, sx1 - sx0, sy1 - sy0);
  }

  // vehicle outlines in units of the vehicle's length, bow at +y (rotated by heading)
  const SHAPES = {
    kayak: [[0, 0.5], [0.08, 0.3], [0.1, 0], [0.08, -0.3], [0, -0.5], [-0.08, -0.3], [-0.1, 0], [-0.08, 0.3]],
    auv: [[0, 0.5], [0.1, 0.4], [0.1, -0.35], [0.2, -0.5], [-0.2, -0.5], [-0.1, -0.35], [-0.1, 0.4]],
    ship: [[0, 0.5], [0.15, 0.25], [0.15, -0.5], [-0.15, -0.5], [-0.15, 0.25]],
    glider: [[0, 0.5], [0.05, 0.1], [0.45, -0.05], [0.45, -0.12], [0.05, -0.1], [0.04, -0.5], [-0.04, -0.5], [-0.05, -0.1], [-0.45, -0.12], [-0.45, -0.05], [-0.05, 0.1]],
    heron: [[0, 0.5], [0.22, 0.2], [0.22, -0.5], [-0.22, -0.5], [-0.22, 0.2]],
    other: [[0, 0.5], [0.3, -0.5], [0, -0.3], [-0.3, -0.5]]
  };
  function shapeOf(type) {
    const t = (type || '').toLowerCase();
    if (t === 'kayak' || t === 'usv') return ['kayak', 4];
    if (t === 'auv' || t === 'uuv') return ['auv', 4];
    if (t === 'ship' || t === 'boat' || t === 'cray' || t === 'longship') return ['ship', 10];
    if (t === 'glider' || t === 'wglider') return ['glider', 2];
    if (t === 'heron' || t === 'mokai') return ['heron', 2];
    return ['other', 4];
  }
  function drawVehicles() {
    const vs = Object.values(S.vehicles);
    ctx.lineWidth = 1;
    for (const v of vs) { // trails first, under every vehicle
      if (v.trail.length < 2) continue;
      ctx.strokeStyle = v.stale ? 'rgba(150,150,150,0.5)' : 'rgba(255,255,255,0.45)';
      ctx.beginPath();
      let [px, py] = toScreen(v.trail[0][0], v.trail[0][1]);
      ctx.moveTo(px, py);
      for (let i = 1; i < v.trail.length; i++) { [px, py] = toScreen(v.trail[i][0], v.trail[i][1]); ctx.lineTo(px, py); }
      ctx.stroke();
    }
    ctx.font = '11px sans-serif';
    for (const v of vs) {
      const [name, dlen] = shapeOf(v.type), pts = SHAPES[name];
      const len = Math.max(v.len || dlen, 26 / S.view.scale); // at least 26 px long
      const [sx, sy] = toScreen(v.x, v.y);
      if (sx < -50 || sy < -50 || sx > canvas.width + 50 || sy > canvas.height + 50) continue;
      const a = (v.hdg || 0) * D2R, ca = Math.cos(a), sa = Math.sin(a), k = len * S.view.scale;
      ctx.beginPath();
      for (let i = 0; i < pts.length; i++) { // heading clockwise from north; screen y grows down
        const px = pts[i][0] * k, py = pts[i][1] * k;
        const rx = px * ca + py * sa, ry = -px * sa + py * ca;
        if (i) ctx.lineTo(sx + rx, sy - ry); else ctx.moveTo(sx + rx, sy - ry);
      }
      ctx.closePath();
      ctx.fillStyle = v.stale ? '#8a8a8a' : colour(v.color, '#ffd700');
      ctx.fill();
      ctx.strokeStyle = v.name === S.selected ? '#ff4040' : 'rgba(0,0,0,0.7)';
      ctx.lineWidth = v.name === S.selected ? 2 : 1;
      ctx.stroke();
      ctx.fillStyle = v.stale ? '#aaa' : '#fff';
      ctx.fillText(v.stale ? v.name + ' (stale)' : v.name, sx + 10, sy - 8);
    }
  }
  function pathOf(pts, close) {
    ctx.beginPath();
    pts.forEach((p, i) => { const [sx, sy] = toScreen(p[0], p[1]); if (i) ctx.lineTo(sx, sy); else ctx.moveTo(sx, sy); });
    if (close) ctx.closePath();
  }
  function fillAlpha(c, f) { ctx.globalAlpha = Math.max(0, Math.min(1, f)); ctx.fillStyle = c; ctx.fill(); ctx.globalAlpha = 1; }
  function drawArtifacts() {
    const now = modelNow();
    ctx.font = '11px sans-serif';
    for (const a of Object.values(S.artifacts)) {
      const edge = colour(a.edge_color, a.kind === 'seglist' ? 'white' : 'yellow');
      const fill = colour(a.fill_color, edge);
      ctx.lineWidth = Math.max(1, a.edge_size || 1);
      ctx.strokeStyle = edge;
      if (a.kind === 'polygon' || a.kind === 'seglist') {
        if (!a.pts.length) continue;
        pathOf(a.pts, a.kind === 'polygon');
        if (a.kind === 'polygon' && a.fill > 0) fillAlpha(fill, a.fill);
        ctx.stroke();
        const vs = a.vertex_size || 2;
        ctx.fillStyle = colour(a.vertex_color, edge);
        for (const p of a.pts) { const [sx, sy] = toScreen(p[0], p[1]); ctx.fillRect(sx - vs / 2, sy - vs / 2, vs, vs); }
        const [lx, ly] = toScreen(a.pts[0][0], a.pts[0][1]);
        if (a.label && a.kind === 'polygon') { ctx.fillStyle = colour(a.label_color, edge); ctx.fillText(a.label, lx + 4, ly - 4); }
      } else if (a.kind === 'circle') {
        const [sx, sy] = toScreen(a.x, a.y);
        ctx.beginPath(); ctx.arc(sx, sy, a.radius * S.view.scale, 0, 2 * Math.PI);
        if (a.fill > 0) fillAlpha(fill, a.fill);
        ctx.stroke();
      } else if (a.kind === 'point') {
        const [sx, sy] = toScreen(a.x, a.y), r = Math.max(2, (a.vertex_size || 4) / 2);
        ctx.fillStyle = colour(a.vertex_color, colour(a.fill_color, 'yellow'));
        ctx.beginPath(); ctx.arc(sx, sy, r, 0, 2 * Math.PI); ctx.fill();
        if (a.label) { ctx.fillStyle = colour(a.label_color, '#ddd'); ctx.fillText(a.label, sx + 5, sy - 5); }
      } else if (a.kind === 'marker') {
        const [sx, sy] = toScreen(a.x, a.y), r = Math.max(5, (a.width || 4) * S.view.scale / 2);
        const t = (a.type || 'circle').toLowerCase();
        ctx.beginPath();
        if (t === 'square' || t === 'efield') ctx.rect(sx - r, sy - r, 2 * r, 2 * r);
        else if (t === 'diamond') { ctx.moveTo(sx, sy - r); ctx.lineTo(sx + r, sy); ctx.lineTo(sx, sy + r); ctx.lineTo(sx - r, sy); ctx.closePath(); }
        else if (t === 'triangle' || t === 'gateway') { ctx.moveTo(sx, sy - r); ctx.lineTo(sx + r, sy + r); ctx.lineTo(sx - r, sy + r); ctx.closePath(); }
        else ctx.arc(sx, sy, r, 0, 2 * Math.PI);
        ctx.fillStyle = colour(a.fill_color, 'orange'); ctx.fill();
        ctx.strokeStyle = colour(a.edge_color, 'black'); ctx.lineWidth = 1; ctx.stroke();
        if (a.label || a.msg) { ctx.fillStyle = colour(a.label_color, '#fff'); ctx.fillText(a.msg || a.label, sx + r + 3, sy - r); }
      } else if (a.kind === 'range_pulse') {
        const age = now - a.t, d = a.duration || 15;
        if (age < 0 || age > d) continue;
        const [sx, sy] = toScreen(a.x, a.y), r = a.radius * (age / d) * S.view.scale, fade = 1 - age / d;
        ctx.beginPath(); ctx.arc(sx, sy, Math.max(1, r), 0, 2 * Math.PI);
        fillAlpha(colour(a.fill_color, 'green'), a.fill * fade);
        ctx.globalAlpha = fade; ctx.strokeStyle = colour(a.edge_color, 'green'); ctx.stroke(); ctx.globalAlpha = 1;
      } else if (a.kind === 'comms_pulse') {
        const age = now - a.t, d = a.duration || 10;
        if (age < 0 || age > d) continue;
        const fade = 1 - age / d, dx = a.tx - a.x, dy = a.ty - a.y, L = Math.hypot(dx, dy) || 1;
        const half = Math.tan((a.beam || 7) * D2R / 2) * L, nx = -dy / L * half, ny = dx / L * half;
        pathOf([[a.x, a.y], [a.tx + nx, a.ty + ny], [a.tx - nx, a.ty - ny]], true);
        fillAlpha(colour(a.fill_color, 'white'), (a.fill || 0.35) * fade);
      }
    }
  }

  let frameTimes = [];
  function draw() {
    const t0 = performance.now();
    const w = canvas.clientWidth, h = canvas.clientHeight;
    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    if ($('follow').checked) centre();
    else if (S.view.auto && S.frames % 30 === 0) fit(); // until the user pans or zooms (Fit: again)
    ctx.fillStyle = '#1d3b57';
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    drawImage();
    drawGrid();
    drawArtifacts();
    drawVehicles();
    const nv = Object.keys(S.vehicles).length;
    $('status').textContent = (S.connected ? '' : 'disconnected  ') + nv + ' vehicles  ' + S.fps + ' fps' +
      (statusText ? '  ' + statusText : '');
    S.frames++;
    const t1 = performance.now();
    S.drawMs = S.drawMs * 0.9 + (t1 - t0) * 0.1;
    frameTimes.push(t1);
    while (frameTimes.length && frameTimes[0] < t1 - 1000) frameTimes.shift();
    S.fps = frameTimes.length;
    if (S.frames % 15 === 0) updatePanel();
    if (castsDirty && S.frames % 10 === 0) updateCasts();
    requestAnimationFrame(draw);
  }

  connect();
  requestAnimationFrame(draw);
})();
