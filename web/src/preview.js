// A lobby card's picture, drawn by the page on a 2D canvas from what the
// bridge samples of the scenario ({"op":"preview"}, web/bridge/
// shipped_scenarios.cpp: scenarioPreview): the ground's heights and
// surfaces on a 48 x 48 grid, the race track's centre line and width, the
// objects and the cars' starts. Seen from above, north up: each surface in
// the terrain's colours (natural ground by slope), hill-shaded from the
// north-west, the track as asphalt with white edges and a chequered start,
// objects as their footprints and each car as an arrow in its colour. Drawn here
// rather than shipped as images: it always shows the file as it is now, and
// costs the bridge one small grid per scenario (kept).
import * as THREE from 'three';
import { PALETTE, surfaceOf } from './terrain.js';
import { COLORS } from './app.js';

const css = (c) => `#${c.getHexString(THREE.SRGBColorSpace)}`;

export function drawPreview(canvas, m) {
  const g = canvas.getContext('2d');
  const W = canvas.width, H = canvas.height;
  g.fillStyle = '#1b1f24';
  g.fillRect(0, 0, W, H);
  if (!m || !m.grid) return false;
  const { x0, y0, n, step, z, mu } = m.grid;
  const side = step * (n - 1);
  // the grid's square fitted to the canvas' width (a wide card shows its middle band)
  const scale = W / side, cx = x0 + side / 2, cy = y0 + side / 2;
  const px = (x) => W / 2 + (x - cx) * scale, py = (y) => H / 2 - (y - cy) * scale;
  const at = (i, j) => {
    const h = z[Math.min(n - 1, Math.max(0, i)) * n + Math.min(n - 1, Math.max(0, j))];
    return h === null ? 0 : h;
  };
  const img = g.createImageData(W, H), c = new THREE.Color(), sun = new THREE.Vector3(-0.5, 0.6, 0.62).normalize();
  const v = new THREE.Vector3(), rgb = { r: 0, g: 0, b: 0 };
  for (let y = 0; y < H; ++y) for (let x = 0; x < W; ++x) {
    const wx = cx + (x - W / 2) / scale, wy = cy - (y - H / 2) / scale;
    const j = Math.round((wx - x0) / step), i = Math.round((wy - y0) / step);
    if (i < 0 || j < 0 || i >= n || j >= n || z[i * n + j] === null) continue;
    v.set(-(at(i, j + 1) - at(i, j - 1)) / (2 * step), -(at(i + 1, j) - at(i - 1, j)) / (2 * step), 1).normalize();
    const k = mu && mu[i * n + j] !== null && mu[i * n + j] !== undefined ? mu[i * n + j] : null;
    if (k === null) {
      const slope = Math.acos(Math.min(1, v.z));
      c.copy(PALETTE.grass).lerp(PALETTE.earth, Math.min(1, Math.max(0, (slope - 0.33) / 0.17)));
      if (typeof m.friction === 'number' && m.friction !== 1 && surfaceOf(m.friction) !== 'grass') c.copy(PALETTE[surfaceOf(m.friction)]);
    } else c.copy(PALETTE[surfaceOf(k)]);
    const shade = 0.55 + 0.55 * Math.max(0, v.dot(sun));
    c.multiplyScalar(shade);
    const o = 4 * (y * W + x);
    c.getRGB(rgb, THREE.SRGBColorSpace);
    img.data[o] = 255 * rgb.r; img.data[o + 1] = 255 * rgb.g; img.data[o + 2] = 255 * rgb.b; img.data[o + 3] = 255;
  }
  g.putImageData(img, 0, 0);
  // the track
  const t = m.track;
  if (t && t.centerline && t.centerline.length > 1) {
    const path = () => {
      g.beginPath();
      t.centerline.forEach(([x, y], k) => (k ? g.lineTo(px(x), py(y)) : g.moveTo(px(x), py(y))));
      if (t.closed) g.closePath();
    };
    g.lineJoin = 'round';
    g.lineCap = 'butt';
    path(); g.strokeStyle = '#f2f2f2'; g.lineWidth = Math.max(3, 2 * t.half_width * scale + 2); g.stroke();
    path(); g.strokeStyle = css(PALETTE.asphalt); g.lineWidth = Math.max(2, 2 * t.half_width * scale); g.stroke();
    // the start: a chequered bar across the first segment
    const [[ax, ay], [bx, by]] = t.centerline;
    const L = Math.hypot(bx - ax, by - ay) || 1, nx = -(by - ay) / L, ny = (bx - ax) / L;
    g.strokeStyle = '#fff'; g.lineWidth = 3; g.setLineDash([2, 2]);
    g.beginPath();
    g.moveTo(px(ax + nx * t.half_width), py(ay + ny * t.half_width));
    g.lineTo(px(ax - nx * t.half_width), py(ay - ny * t.half_width));
    g.stroke();
    g.setLineDash([]);
  }
  // objects: footprints (a box turned by its yaw; a disc otherwise), at least 2 px
  g.fillStyle = 'rgba(225,222,214,0.95)';
  g.strokeStyle = 'rgba(40,40,40,0.9)';
  g.lineWidth = 0.5;
  for (const [x, y, sx, sy, yaw] of m.objects || []) {
    const a = Math.max(2, sx * scale), b = Math.max(2, sy * scale);
    g.save();
    g.translate(px(x), py(y));
    g.rotate(-yaw);
    g.beginPath();
    if (sx === sy) g.arc(0, 0, a / 2, 0, 2 * Math.PI); else g.rect(-a / 2, -b / 2, a, b);
    g.fill(); g.stroke();
    g.restore();
  }
  (m.cars || []).forEach(([x, y, yaw], k) => {
    const s = 5, X = px(x), Y = py(y), cs = Math.cos(yaw), sn = Math.sin(yaw);
    g.fillStyle = css(new THREE.Color(COLORS[k % COLORS.length]));
    g.strokeStyle = '#000';
    g.lineWidth = 1;
    g.beginPath();
    g.moveTo(X + s * cs, Y - s * sn);
    g.lineTo(X - s * cs + 0.6 * s * sn, Y + s * sn + 0.6 * s * cs);
    g.lineTo(X - s * cs - 0.6 * s * sn, Y + s * sn - 0.6 * s * cs);
    g.closePath();
    g.fill(); g.stroke();
  });
  return true;
}
