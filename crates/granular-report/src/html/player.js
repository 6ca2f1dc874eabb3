// granular report: the snapshot player, written by hand (no library, no network).
// It reads the JSON in #granular-data (written by granular-report's html/player.rs),
// draws the grains of a frame on #grains at true size (2D: disks; 3D: shaded spheres in
// orthographic projection, far ones first; drag to rotate) and the frame's speed
// histogram against Maxwell-Boltzmann on #histogram. What it drew is kept in data
// attributes of the canvases (frame, time, drawn grains, pixel scale and origin), which
// the browser test reads back.
(function () {
  'use strict';
  var data = JSON.parse(document.getElementById('granular-data').textContent);
  var D = data.dimension, L = data.lengths, periodic = data.periodic;
  var SPECIES_COLOURS = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd',
    '#8c564b', '#e377c2', '#7f7f7f', '#bcbd22', '#17becf'];
  var VIRIDIS = [[68, 1, 84], [72, 40, 120], [62, 74, 137], [49, 104, 142], [38, 130, 142],
    [31, 158, 137], [53, 183, 121], [109, 205, 89], [180, 222, 44], [253, 231, 37]];
  var LEVELS = 64;
  var BACKGROUND = '#eef0f3', BOX = '#ffffff';

  function bytes(s) {
    var b = atob(s), u = new Uint8Array(b.length);
    for (var i = 0; i < b.length; i++) u[i] = b.charCodeAt(i);
    return u;
  }
  function floats(s) { var u = bytes(s); return new Float32Array(u.buffer, 0, u.length >> 2); }

  var radii = floats(data.radii), species = bytes(data.species), n = radii.length;
  var cache = [];
  function frameData(i) {
    if (!cache[i]) {
      var f = data.frames[i];
      cache[i] = { pos: floats(f.positions), speed: floats(f.speeds) };
    }
    return cache[i];
  }

  var speedColours = [];
  for (var l = 0; l < LEVELS; l++) {
    var x = l / (LEVELS - 1) * (VIRIDIS.length - 1), k = Math.min(Math.floor(x), VIRIDIS.length - 2), f = x - k;
    var c = [0, 1, 2].map(function (j) { return Math.round(VIRIDIS[k][j] * (1 - f) + VIRIDIS[k + 1][j] * f); });
    speedColours.push('rgb(' + c.join(',') + ')');
  }
  function speedLevel(v) { return Math.max(0, Math.min(LEVELS - 1, Math.floor(v / data.speed_max * LEVELS))); }
  function speciesColour(s) { return SPECIES_COLOURS[s % SPECIES_COLOURS.length]; }

  var canvas = document.getElementById('grains'), ctx = canvas.getContext('2d');
  var hist = document.getElementById('histogram'), hctx = hist.getContext('2d');
  var slider = document.getElementById('frame'), label = document.getElementById('frame-label');
  var playButton = document.getElementById('play'), colourSelect = document.getElementById('colour');
  var legend = document.getElementById('legend');
  var dpr = window.devicePixelRatio || 1;
  var current = 0, yaw = 0.6, pitch = 0.35;
  colourSelect.value = data.species_names.length > 1 ? 'species' : 'speed';

  function size(c, cssW, cssH) {
    c.width = Math.round(cssW * dpr); c.height = Math.round(cssH * dpr);
    c.style.width = cssW + 'px'; c.style.height = cssH + 'px';
  }
  var cssW = Math.max(300, Math.min(640, window.innerWidth - 620)), cssH = cssW;
  if (D === 2) {
    var aspect = L[1] / L[0];
    cssH = cssW * aspect;
    if (cssH > 640) { cssH = 640; cssW = cssH / aspect; }
  }
  size(canvas, Math.round(cssW), Math.round(cssH));
  size(hist, 440, 320);
  var margin = 8 * dpr;
  var scale = D === 2 ? (canvas.width - 2 * margin) / L[0]
    : (canvas.width - 2 * margin) / Math.sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
  var originX = margin, originY = canvas.height - margin;
  canvas.dataset.scale = scale;
  canvas.dataset.originX = originX;
  canvas.dataset.originY = originY;
  canvas.dataset.background = BACKGROUND;
  canvas.dataset.box = BOX;
  canvas.dataset.speciesColours = JSON.stringify(data.species_names.map(function (_, s) { return speciesColour(s); }));

  function colourKey(fd, j, bySpecies) { return bySpecies ? species[j] : speedLevel(fd.speed[j]); }
  function colourOf(key, bySpecies) { return bySpecies ? speciesColour(key) : speedColours[key]; }

  function images(x, r, axis) {
    var out = [x];
    if (periodic[axis]) {
      if (x - r < 0) out.push(x + L[axis]);
      if (x + r > L[axis]) out.push(x - L[axis]);
    }
    return out;
  }

  function draw2d(fd, bySpecies) {
    ctx.fillStyle = BACKGROUND; ctx.fillRect(0, 0, canvas.width, canvas.height);
    var bw = L[0] * scale, bh = L[1] * scale;
    ctx.fillStyle = BOX; ctx.fillRect(originX, originY - bh, bw, bh);
    ctx.save();
    ctx.beginPath(); ctx.rect(originX, originY - bh, bw, bh); ctx.clip();
    var paths = {}, drawn = 0;
    for (var j = 0; j < n; j++) {
      var x = fd.pos[2 * j], y = fd.pos[2 * j + 1], r = radii[j];
      var key = colourKey(fd, j, bySpecies), p = paths[key] || (paths[key] = new Path2D());
      var xs = images(x, r, 0), ys = images(y, r, 1), rp = r * scale;
      for (var a = 0; a < xs.length; a++) {
        for (var b = 0; b < ys.length; b++) {
          var px = originX + xs[a] * scale, py = originY - ys[b] * scale;
          p.moveTo(px + rp, py); p.arc(px, py, rp, 0, 2 * Math.PI);
        }
      }
      drawn++;
    }
    var outline = radii.length > 0 && radii[0] * scale >= 3;
    ctx.strokeStyle = 'rgba(0,0,0,0.35)'; ctx.lineWidth = dpr * 0.6;
    Object.keys(paths).forEach(function (key) {
      ctx.fillStyle = colourOf(+key, bySpecies); ctx.fill(paths[key]);
      if (outline) ctx.stroke(paths[key]);
    });
    ctx.restore();
    return drawn;
  }

  var sprite = (function () {
    var s = document.createElement('canvas'); s.width = s.height = 64;
    var g = s.getContext('2d'), grad = g.createRadialGradient(22, 22, 0, 32, 32, 32);
    grad.addColorStop(0, 'rgba(255,255,255,0.65)'); grad.addColorStop(0.35, 'rgba(255,255,255,0.05)');
    grad.addColorStop(0.7, 'rgba(0,0,0,0.05)'); grad.addColorStop(1, 'rgba(0,0,0,0.5)');
    g.fillStyle = grad; g.beginPath(); g.arc(32, 32, 32, 0, 2 * Math.PI); g.fill();
    return s;
  })();

  function project(x, y, z) {
    var px = x - L[0] / 2, py = y - L[1] / 2, pz = z - L[2] / 2;
    var x1 = Math.cos(yaw) * px - Math.sin(yaw) * py, y1 = Math.sin(yaw) * px + Math.cos(yaw) * py;
    var y2 = Math.cos(pitch) * y1 - Math.sin(pitch) * pz, z2 = Math.sin(pitch) * y1 + Math.cos(pitch) * pz;
    return [canvas.width / 2 + x1 * scale, canvas.height / 2 - z2 * scale, y2];
  }

  function draw3d(fd, bySpecies) {
    ctx.fillStyle = BACKGROUND; ctx.fillRect(0, 0, canvas.width, canvas.height);
    ctx.strokeStyle = '#9aa3b0'; ctx.lineWidth = dpr;
    for (var e = 0; e < 8; e++) {
      for (var ax = 0; ax < 3; ax++) {
        if (e & (1 << ax)) continue;
        var c0 = [0, 1, 2].map(function (q) { return (e >> q & 1) * L[q]; }), c1 = c0.slice();
        c1[ax] = L[ax];
        var a = project(c0[0], c0[1], c0[2]), b = project(c1[0], c1[1], c1[2]);
        ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
      }
    }
    var screen = new Float32Array(3 * n), order = new Array(n);
    for (var j = 0; j < n; j++) {
      var p = project(fd.pos[3 * j], fd.pos[3 * j + 1], fd.pos[3 * j + 2]);
      screen[3 * j] = p[0]; screen[3 * j + 1] = p[1]; screen[3 * j + 2] = p[2]; order[j] = j;
    }
    order.sort(function (i, k) { return screen[3 * k + 2] - screen[3 * i + 2]; });
    for (var m = 0; m < n; m++) {
      var i = order[m], rp = radii[i] * scale, X = screen[3 * i], Y = screen[3 * i + 1];
      ctx.fillStyle = colourOf(colourKey(fd, i, bySpecies), bySpecies);
      ctx.beginPath(); ctx.arc(X, Y, rp, 0, 2 * Math.PI); ctx.fill();
      if (rp >= 1.5) ctx.drawImage(sprite, X - rp, Y - rp, 2 * rp, 2 * rp);
    }
    return n;
  }

  function fmt(x) { return x === null || !isFinite(x) ? '—' : Number(x).toPrecision(4); }

  function drawHistogram(i) {
    var h = data.frames[i].histogram, W = hist.width, H = hist.height, s = dpr;
    var left = 52 * s, right = 12 * s, top = 30 * s, bottom = 40 * s;
    var total = h.counts.reduce(function (a, b) { return a + b; }, 0);
    var dens = h.counts.map(function (c) { return c / (data.grains_total * h.width); });
    var ymax = 1.1 * Math.max(Math.max.apply(null, dens), Math.max.apply(null, h.theory)) || 1;
    var vmax = h.width * h.counts.length;
    function X(v) { return left + v / vmax * (W - left - right); }
    function Y(p) { return H - bottom - p / ymax * (H - top - bottom); }
    hctx.fillStyle = '#fff'; hctx.fillRect(0, 0, W, H);
    hctx.fillStyle = '#9bb8dd';
    dens.forEach(function (d, b) { hctx.fillRect(X(b * h.width), Y(d), X((b + 1) * h.width) - X(b * h.width) - 0.5 * s, Y(0) - Y(d)); });
    hctx.strokeStyle = '#c0392b'; hctx.lineWidth = 2 * s; hctx.beginPath();
    h.theory.forEach(function (t, b) {
      var x = X((b + 0.5) * h.width);
      if (b === 0) hctx.moveTo(x, Y(t)); else hctx.lineTo(x, Y(t));
    });
    hctx.stroke();
    hctx.strokeStyle = '#333'; hctx.lineWidth = s; hctx.beginPath();
    hctx.moveTo(left, top); hctx.lineTo(left, H - bottom); hctx.lineTo(W - right, H - bottom); hctx.stroke();
    hctx.fillStyle = '#333'; hctx.font = (12 * s) + 'px sans-serif'; hctx.textAlign = 'center';
    for (var t = 0; t <= 4; t++) {
      hctx.fillText(fmt(vmax * t / 4), X(vmax * t / 4), H - bottom + 15 * s);
      hctx.textAlign = 'right'; hctx.fillText(fmt(ymax * t / 4), left - 4 * s, Y(ymax * t / 4) + 4 * s); hctx.textAlign = 'center';
    }
    hctx.fillText('speed v', (left + W - right) / 2, H - 6 * s);
    hctx.textAlign = 'left';
    var temps = h.temperatures.map(fmt).join(', ');
    hctx.fillText('t = ' + fmt(data.frames[i].time) + ', T = ' + temps + '   p(v)', left, 18 * s);
    hist.dataset.frame = i;
    hist.dataset.total = total;
  }

  function updateLegend(bySpecies) {
    if (bySpecies) {
      legend.innerHTML = data.species_names.map(function (name, s) {
        return '<span class="swatch" style="background:' + speciesColour(s) + '"></span>' + name.replace(/[&<>"]/g, '');
      }).join('');
    } else {
      legend.innerHTML = 'speed 0 <span class="bar" style="background:linear-gradient(to right,' +
        speedColours.filter(function (_, q) { return q % 8 === 0 || q === LEVELS - 1; }).join(',') +
        ')"></span> ' + fmt(data.speed_max);
    }
  }

  function show(i) {
    current = i;
    var bySpecies = colourSelect.value === 'species', fd = frameData(i);
    var drawn = D === 2 ? draw2d(fd, bySpecies) : draw3d(fd, bySpecies);
    canvas.dataset.frame = i;
    canvas.dataset.time = data.frames[i].time;
    canvas.dataset.drawn = drawn;
    canvas.dataset.colour = colourSelect.value;
    drawHistogram(i);
    slider.value = i;
    label.textContent = 'frame ' + (i + 1) + ' of ' + data.frames.length + ' · t = ' + fmt(data.frames[i].time);
    updateLegend(bySpecies);
  }

  var playing = false, last = 0, FRAME_MS = 125;
  function tick(now) {
    if (!playing) return;
    if (now - last >= FRAME_MS) { last = now; show((current + 1) % data.frames.length); }
    requestAnimationFrame(tick);
  }
  playButton.addEventListener('click', function () {
    playing = !playing; playButton.textContent = playing ? 'Pause' : 'Play';
    if (playing) requestAnimationFrame(tick);
  });
  slider.addEventListener('input', function () { show(+slider.value); });
  colourSelect.addEventListener('change', function () { show(current); });
  if (D === 3) {
    var dragging = null;
    canvas.addEventListener('pointerdown', function (e) { dragging = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); });
    canvas.addEventListener('pointerup', function () { dragging = null; });
    canvas.addEventListener('pointermove', function (e) {
      if (!dragging) return;
      yaw += (e.clientX - dragging[0]) * 0.01;
      pitch = Math.max(-1.5, Math.min(1.5, pitch + (e.clientY - dragging[1]) * 0.01));
      dragging = [e.clientX, e.clientY];
      show(current);
    });
  }
  document.getElementById('player-caption').textContent = D === 2
    ? data.grains_shown + ' disks at true size, box ' + L.join(' × ') + (periodic.some(Boolean) ? ' (periodic images drawn at the edges)' : '') + '.'
    : data.grains_shown + ' spheres at true size in orthographic projection, far ones first; drag to rotate.';
  // The first frame shown: 0, or `#frame=N` / `#frame=last` in the page's address.
  var wanted = /frame=(\d+|last)/.exec(location.hash), lastFrame = data.frames.length - 1;
  show(wanted ? (wanted[1] === 'last' ? lastFrame : Math.min(lastFrame, +wanted[1])) : 0);
  canvas.dataset.ready = '1';
})();
