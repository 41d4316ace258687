"use strict";
// The animation page's viewer: no libraries, no network. It reads the scene from the JSON
// block `scene-data` (written by src/output/animation/mod.rs) and draws it on a 2D canvas
// with an orthographic camera. `#t=0.5` in the URL shows that time, paused (for tests
// and for links to a moment); the root element's data-status becomes "ok" after the first
// frame is drawn, or "error: ..." if anything throws.
(function () {
  const root = document.documentElement;
  window.addEventListener("error", (e) => { root.dataset.status = "error: " + e.message; });

  const scene = JSON.parse(document.getElementById("scene-data").textContent);
  const times = scene.times;
  const frames = times.length;
  const np = scene.points.length;
  const view = document.getElementById("view");
  const ctx = view.getContext("2d");
  const slider = document.getElementById("slider");
  const clock = document.getElementById("clock");
  const playButton = document.getElementById("play");
  const speedSelect = document.getElementById("speed");
  const tracesBox = document.getElementById("traces");
  document.getElementById("note").textContent = scene.note;
  slider.max = String(Math.max(frames - 1, 0));

  // Position of point i in frame f.
  const at = (f, i) => {
    const o = 3 * (f * np + i);
    return [scene.positions[o], scene.positions[o + 1], scene.positions[o + 2]];
  };

  // Bounding box of every point over every frame: the camera's centre and scale.
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let f = 0; f < frames; f++) {
    for (let i = 0; i < np; i++) {
      const p = at(f, i);
      for (let k = 0; k < 3; k++) {
        lo[k] = Math.min(lo[k], p[k]);
        hi[k] = Math.max(hi[k], p[k]);
      }
    }
  }
  const centre = [0, 1, 2].map((k) => (np ? 0.5 * (lo[k] + hi[k]) : 0));
  const extent = [0, 1, 2].map((k) => (np ? hi[k] - lo[k] : 1));
  const size = Math.max(...extent, 1e-9);

  // Camera: yaw about world z, then pitch; the initial view looks along the axis in
  // which the motion is thinnest (a planar mechanism is seen face on), zoomed so that every
  // point of every frame, with its ground symbol and label, stays inside the canvas.
  const camera = { yaw: 0, pitch: 0, zoom: 1, panX: 0, panY: 0 };
  function resetCamera() {
    const thin = extent.indexOf(Math.min(...extent));
    // Along x: y right, z up; along y: x right, z up; along z: x right, y up.
    const [yaw, pitch] = [[Math.PI / 2, 0], [0, 0], [0, Math.PI / 2]][thin];
    Object.assign(camera, { yaw, pitch, zoom: 1, panX: 0, panY: 0 });
    if (extent[thin] > 0.2 * size) {
      // Spatial motion, thick in every direction: a three-quarter view shows depth.
      Object.assign(camera, { yaw: 0.6, pitch: 0.45 });
    }
    // Margins (px) for the symbols drawn around a point: a label above and to the right,
    // a ground triangle and hatching below.
    const [left, right, top, bottom] = [20, 90, 30, 32];
    let fit = Infinity;
    const s0 = scaleAt(1);
    for (let f = 0; f < frames; f++) {
      for (let i = 0; i < np; i++) {
        const [px, py] = project(at(f, i));
        const dx = (px - view.width / 2) / s0, dy = (py - view.height / 2) / s0;
        if (dx > 1e-12) fit = Math.min(fit, (view.width / 2 - right) / dx);
        if (dx < -1e-12) fit = Math.min(fit, (view.width / 2 - left) / -dx);
        if (dy > 1e-12) fit = Math.min(fit, (view.height / 2 - bottom) / dy);
        if (dy < -1e-12) fit = Math.min(fit, (view.height / 2 - top) / -dy);
      }
    }
    camera.zoom = Number.isFinite(fit) && fit > 0 ? fit / s0 : 1;
  }

  // World point -> canvas pixel. With yaw = pitch = 0 the screen shows x to the right and
  // z up (looking along +y); pitch = pi/2 looks down from +z (x right, y up).
  function project(p) {
    const x = p[0] - centre[0], y = p[1] - centre[1], z = p[2] - centre[2];
    const cy = Math.cos(camera.yaw), sy = Math.sin(camera.yaw);
    const cp = Math.cos(camera.pitch), sp = Math.sin(camera.pitch);
    const u = cy * x + sy * y; // screen right
    const w = -sy * x + cy * y; // depth before pitch
    const v = cp * z + sp * w; // screen up
    const s = scaleAt(camera.zoom);
    return [view.width / 2 + camera.panX + s * u, view.height / 2 + camera.panY - s * v];
  }

  // Pixels per metre at `zoom`.
  function scaleAt(zoom) {
    return (0.8 * Math.min(view.width, view.height) / size) * zoom;
  }
  resetCamera();

  let time = times.length ? times[0] : 0;
  let playing = false;
  const hash = /[#&]t=([-+0-9.eE]+)/.exec(location.hash);
  if (hash) time = Math.min(Math.max(parseFloat(hash[1]), times[0]), times[frames - 1]);

  // The frame at or before `t` (binary search).
  function frameAt(t) {
    let a = 0, b = frames - 1;
    while (a < b) {
      const m = (a + b + 1) >> 1;
      if (times[m] <= t) a = m; else b = m - 1;
    }
    return a;
  }

  const colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"];

  function drawScene(f) {
    ctx.clearRect(0, 0, view.width, view.height);
    if (tracesBox.checked) {
      ctx.lineWidth = 1.5;
      scene.traces.forEach((i, k) => {
        ctx.strokeStyle = colours[(k + 3) % colours.length] + "99";
        ctx.beginPath();
        for (let g = 0; g <= f; g++) {
          const [px, py] = project(at(g, i));
          if (g === 0) ctx.moveTo(px, py); else ctx.lineTo(px, py);
        }
        ctx.stroke();
      });
    }
    ctx.lineCap = "round";
    ctx.lineJoin = "round";
    scene.lines.forEach((line, k) => {
      ctx.strokeStyle = colours[k % colours.length];
      ctx.lineWidth = 6;
      ctx.beginPath();
      line.forEach((i, j) => {
        const [px, py] = project(at(f, i));
        if (j === 0) ctx.moveTo(px, py); else ctx.lineTo(px, py);
      });
      ctx.stroke();
    });
    ctx.font = "13px system-ui, sans-serif";
    const labels = [];
    scene.points.forEach((p, i) => {
      const [px, py] = project(at(f, i));
      ctx.lineWidth = 2;
      ctx.strokeStyle = "#222";
      if (p.ground) {
        // A ground point: a hatched triangle under it.
        ctx.fillStyle = "#bbb";
        ctx.beginPath();
        ctx.moveTo(px, py);
        ctx.lineTo(px - 10, py + 16);
        ctx.lineTo(px + 10, py + 16);
        ctx.closePath();
        ctx.fill();
        ctx.stroke();
        ctx.beginPath();
        for (let h = -12; h <= 8; h += 5) {
          ctx.moveTo(px + h, py + 22);
          ctx.lineTo(px + h + 4, py + 16);
        }
        ctx.stroke();
      }
      ctx.fillStyle = "#fff";
      ctx.beginPath();
      ctx.arc(px, py, 5, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
      // Points that coincide (the two halves of a joint) share one label: "B1 = A2".
      const same = labels.find((l) => Math.abs(l[0] - px) < 0.5 && Math.abs(l[1] - py) < 0.5);
      if (same) same[2] += " = " + p.name; else labels.push([px, py, p.name]);
    });
    // A label whose box would overlap one already drawn is left out (a chain of 40 loops
    // would print its 160 names on top of each other).
    ctx.fillStyle = "#444";
    const drawn = [];
    labels.forEach(([px, py, text]) => {
      const box = [px + 8, py - 21, px + 8 + ctx.measureText(text).width, py - 8];
      const clash = drawn.some((b) => box[0] < b[2] + 4 && b[0] < box[2] + 4 && box[1] < b[3] + 2 && b[1] < box[3] + 2);
      if (clash) return;
      drawn.push(box);
      ctx.fillText(text, px + 8, py - 8);
    });
  }

  // The magnitude of each unit's values across the mechanism: a coordinate whose spread is
  // below 1e-12 of it is round-off around a constant and is drawn flat.
  const unitScale = {};
  scene.coordinates.forEach((c) => {
    const m = Math.max(...c.values.map(Math.abs).filter(Number.isFinite), 0);
    unitScale[c.unit] = Math.max(unitScale[c.unit] || 0, m);
  });
  // A value for an axis: 4 significant digits, 0 for round-off below `tiny`.
  const axisValue = (v, tiny) => (Math.abs(v) <= tiny ? "0" : Number(v.toPrecision(4)).toString());

  // Coordinate plots: drawn once into an image, then the cursor on top at every frame.
  const plots = scene.coordinates.map((c) => {
    const canvas = document.createElement("canvas");
    canvas.width = 520;
    canvas.height = 120;
    document.getElementById("plots").appendChild(canvas);
    const g = canvas.getContext("2d");
    let ymin = Math.min(...c.values), ymax = Math.max(...c.values);
    const tiny = 1e-12 * Math.max(unitScale[c.unit], Math.abs(ymin), Math.abs(ymax));
    if (ymax - ymin <= tiny) {
      // Constant to round-off: centred, with +-10 % of the unit's scale around it.
      const mid = Math.abs(ymin + ymax) / 2 <= tiny ? 0 : (ymin + ymax) / 2;
      const pad = Math.max(0.1 * Math.abs(mid), 0.1 * unitScale[c.unit], 1e-3);
      [ymin, ymax] = [mid - pad, mid + pad];
    }
    const span = ymax - ymin || 1;
    const t0 = times[0], t1 = times[frames - 1] || 1;
    const x = (t) => 50 + ((t - t0) / (t1 - t0 || 1)) * (canvas.width - 60);
    const y = (v) => canvas.height - 20 - ((v - ymin) / span) * (canvas.height - 35);
    g.fillStyle = "#fff";
    g.fillRect(0, 0, canvas.width, canvas.height);
    g.strokeStyle = "#ccc";
    g.strokeRect(50, 15, canvas.width - 60, canvas.height - 35);
    g.fillStyle = "#333";
    g.font = "12px system-ui, sans-serif";
    g.fillText(c.name + (c.unit ? " (" + c.unit + ")" : ""), 54, 12);
    g.fillText(axisValue(ymax, tiny), 2, 20);
    g.fillText(axisValue(ymin, tiny), 2, canvas.height - 20);
    g.fillText("t (s)", canvas.width - 40, canvas.height - 4);
    g.strokeStyle = "#1f77b4";
    g.lineWidth = 1.5;
    g.beginPath();
    c.values.forEach((v, k) => {
      if (k === 0) g.moveTo(x(times[k]), y(v)); else g.lineTo(x(times[k]), y(v));
    });
    g.stroke();
    return { g, x, image: g.getImageData(0, 0, canvas.width, canvas.height), canvas };
  });

  function drawCursors(t) {
    for (const p of plots) {
      p.g.putImageData(p.image, 0, 0);
      p.g.strokeStyle = "#d62728";
      p.g.lineWidth = 1.5;
      p.g.beginPath();
      p.g.moveTo(p.x(t), 15);
      p.g.lineTo(p.x(t), p.canvas.height - 20);
      p.g.stroke();
    }
  }

  function render() {
    const f = frameAt(time);
    drawScene(f);
    drawCursors(times[f]);
    slider.value = String(f);
    clock.textContent = "t = " + times[f].toFixed(3) + " s";
  }

  let last = null;
  function tick(now) {
    if (playing) {
      if (last !== null) time += ((now - last) / 1000) * parseFloat(speedSelect.value);
      if (time > times[frames - 1]) time = times[0];
      last = now;
      render();
      requestAnimationFrame(tick);
    }
  }
  function setPlaying(on) {
    playing = on && frames > 1;
    playButton.textContent = playing ? "Pause" : "Play";
    last = null;
    if (playing) requestAnimationFrame(tick);
  }
  playButton.addEventListener("click", () => setPlaying(!playing));
  slider.addEventListener("input", () => {
    setPlaying(false);
    time = times[parseInt(slider.value, 10)];
    render();
  });
  tracesBox.addEventListener("change", render);

  // Orbit, pan and zoom.
  let drag = null;
  view.addEventListener("contextmenu", (e) => e.preventDefault());
  view.addEventListener("mousedown", (e) => {
    drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 };
  });
  window.addEventListener("mouseup", () => { drag = null; });
  window.addEventListener("mousemove", (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (drag.pan) {
      const k = view.width / view.clientWidth;
      camera.panX += dx * k;
      camera.panY += dy * k;
    } else {
      camera.yaw -= dx * 0.01;
      camera.pitch = Math.max(-Math.PI / 2, Math.min(Math.PI / 2, camera.pitch + dy * 0.01));
    }
    render();
  });
  view.addEventListener("wheel", (e) => {
    e.preventDefault();
    camera.zoom *= Math.exp(-e.deltaY * 0.001);
    render();
  }, { passive: false });
  view.addEventListener("dblclick", () => { resetCamera(); render(); });

  render();
  if (root.dataset.status === "loading") root.dataset.status = "ok";
  if (!hash) setPlaying(true);
})();
