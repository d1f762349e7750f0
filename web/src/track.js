// The race track drawn as a ribbon (docs/front-end.md, Races): the joined
// layout's `track` (web/bridge/race_relay.cpp, trackRibbon) gives the centre
// line resampled every ~1 m, each station's normal and the ground's height
// at lateral offsets every <= 1.5 m, solved from H(x, y, z) = 0 by the
// bridge through the scenario's ground as the terrain's grids are (the page
// never evaluates H). Drawn as one mesh, one draw call, no shadow cast:
//  - the road between the edges, tinted by the surface under its centre
//    (asphalt, wet, grass, snow, ice: the terrain's palette, so grip changes
//    still show), with a fine aggregate texture;
//  - a white edge line 0.25 m wide on each side;
//  - red and white kerbs 1 m wide at both edges where the track turns
//    tighter than a 100 m radius;
//  - a chequered start/finish line across the track at gate 0 and, on a
//    stage, at the last gate.
// Against z-fighting with the terrain under it: the ribbon lies 3 cm above
// the heights (more than a 1.5 m chord's sag on this ground) and is drawn
// with a polygon offset towards the camera.
import * as THREE from 'three';
import { PALETTE, surfaceOf } from './terrain.js';

export const LIFT = 0.03;         // m above the ground's heights
const LINE = 0.25;                // m, the edge lines' width
const KERB = 1.0;                 // m, a kerb's width
const KERB_CURVATURE = 0.01;      // 1/m: kerbs where the radius is under 100 m
const START_LEN = 1.2;            // m, the start/finish line's length along the track
// the atlas: u in [0, .5) aggregate, [.5, .625) kerb stripes, [.625, .75) paint, [.75, 1) chequer
const REGION = { road: [0.01, 0.49], kerb: [0.51, 0.615], paint: [0.64, 0.735], chequer: [0.76, 0.99] };

function atlas() {
  const W = 512, Hh = 256, c = document.createElement('canvas');
  c.width = W; c.height = Hh;
  const g = c.getContext('2d');
  let seed = 11;
  const rnd = () => ((seed = (seed * 16807) % 2147483647) / 2147483647);
  // aggregate: light grey (the vertex colour gives the surface its shade), specks
  g.fillStyle = '#dcdcdc';
  g.fillRect(0, 0, 256, Hh);
  for (let i = 0; i < 14000; ++i) {
    const v = 170 + Math.floor(rnd() * 85);
    g.fillStyle = `rgb(${v},${v},${v})`;
    g.fillRect(rnd() * 256, rnd() * Hh, 1 + rnd(), 1 + rnd());
  }
  // kerb: red then white along v
  g.fillStyle = '#c8231e'; g.fillRect(256, 0, 64, Hh / 2);
  g.fillStyle = '#f4f4f4'; g.fillRect(256, Hh / 2, 64, Hh / 2);
  // paint
  g.fillStyle = '#f4f4f4'; g.fillRect(320, 0, 64, Hh);
  // chequer: 2 across, 4 along
  for (let i = 0; i < 2; ++i) for (let j = 0; j < 4; ++j) {
    g.fillStyle = (i + j) % 2 ? '#111111' : '#f4f4f4';
    g.fillRect(384 + 64 * i, (Hh / 4) * j, 64, Hh / 4);
  }
  const t = new THREE.CanvasTexture(c);
  t.wrapS = THREE.ClampToEdgeWrapping;
  t.wrapT = THREE.RepeatWrapping;
  t.anisotropy = 8;
  t.colorSpace = THREE.SRGBColorSpace;
  return t;
}

// z at lateral offset o of a station's row (linear between the bridge's offsets)
function heightAt(offsets, row, o) {
  const n = offsets.length;
  let j = 0;
  while (j < n - 2 && o > offsets[j + 1]) ++j;
  const a = row[j], b = row[j + 1];
  if (a === null && b === null) return null;
  if (a === null) return b;
  if (b === null) return a;
  const u = Math.min(1, Math.max(0, (o - offsets[j]) / (offsets[j + 1] - offsets[j])));
  return a + u * (b - a);
}

const CELL = 4;  // m, the triangle index's cells (heightAt)
const cellKey = (i, j) => i * 1000003 + j;
// triangle numbers by the xy cells their bounding boxes touch
function indexTriangles(geo, cell) {
  const p = geo.attributes.position.array, ix = geo.index ? geo.index.array : null;
  const n = ix ? ix.length / 3 : p.length / 9, cells = new Map();
  for (let t = 0; t < n; ++t) {
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (let k = 0; k < 3; ++k) {
      const v = ix ? ix[3 * t + k] : 3 * t + k, x = p[3 * v], y = p[3 * v + 1];
      x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
    }
    for (let i = Math.floor(x0 / cell); i <= Math.floor(x1 / cell); ++i)
      for (let j = Math.floor(y0 / cell); j <= Math.floor(y1 / cell); ++j) {
        const key = cellKey(i, j);
        let list = cells.get(key);
        if (!list) cells.set(key, list = []);
        list.push(t);
      }
  }
  return cells;
}

export class TrackRibbon {
  constructor(scene) {
    this.scene = scene;
    this.mesh = null;
    this.texture = null;
    this.track = null;
  }
  // track: layout.track, race: layout.race (gates), or nulls
  set(track, race) {
    this.clear();
    if (!track || !track.xy || track.xy.length < 2) return;
    this.track = track;
    if (!this.texture) this.texture = atlas();
    const geo = this.build(track, race);
    const material = new THREE.MeshLambertMaterial({
      map: this.texture, vertexColors: true, polygonOffset: true, polygonOffsetFactor: -2, polygonOffsetUnits: -4,
    });
    this.mesh = new THREE.Mesh(geo, material);
    this.mesh.name = 'track-ribbon';
    this.mesh.receiveShadow = true;
    this.mesh.renderOrder = 1;  // after the terrain
    this.scene.add(this.mesh);
  }

  build(track, race) {
    const { xy, normal, z, offsets, mu, closed } = track;
    const hw = track.half_width, n = xy.length;
    // arc length and curvature (turn of the normal per metre) at each station
    const s = new Float64Array(n), kerb = new Float64Array(n);
    for (let k = 1; k < n; ++k) s[k] = s[k - 1] + Math.hypot(xy[k][0] - xy[k - 1][0], xy[k][1] - xy[k - 1][1]);
    for (let k = 0; k < n; ++k) {
      const a = closed ? (k + n - 1) % n : Math.max(0, k - 1), b = closed ? (k + 1) % n : Math.min(n - 1, k + 1);
      const turn = Math.abs(Math.atan2(normal[a][0] * normal[b][1] - normal[a][1] * normal[b][0],
        normal[a][0] * normal[b][0] + normal[a][1] * normal[b][1]));
      const d = Math.hypot(xy[b][0] - xy[a][0], xy[b][1] - xy[a][1]);
      kerb[k] = d > 0 && turn / d > KERB_CURVATURE ? KERB : 0;
    }
    // the chequered lines: at gate 0 and, on a stage, at the last gate (nearest stations' arc length)
    const lines = [];
    const gates = (race && race.gates) || [];
    const along = (gx, gy) => {
      let best = 0, bd = Infinity;
      for (let k = 0; k < n; ++k) {
        const d = (xy[k][0] - gx) ** 2 + (xy[k][1] - gy) ** 2;
        if (d < bd) { bd = d; best = k; }
      }
      return s[best];
    };
    for (const g of [gates[0], !closed && gates.length > 1 ? gates[gates.length - 1] : null]) {
      if (g) lines.push(along((g[0] + g[2]) / 2, (g[1] + g[3]) / 2));
    }
    const onLine = (sa, sb) => lines.some((l) => sb > l - START_LEN / 2 && sa < l + START_LEN / 2);

    const pos = [], nor = [], col = [], uv = [], idx = [];
    const white = new THREE.Color(1, 1, 1), tint = new THREE.Color();
    const surface = (k) => tint.copy(PALETTE[surfaceOf(mu ? mu[k] : 1)]);
    // the normal of the ground at (station k, offset o), from the heights
    const up = new THREE.Vector3();
    const groundNormal = (k, o) => {
      const row = z[k], zr = heightAt(offsets, row, o - 0.75), zl = heightAt(offsets, row, o + 0.75);
      const kb = Math.min(n - 1, k + 1), ka = Math.max(0, k - 1);
      const zf = heightAt(offsets, z[kb], o), zb = heightAt(offsets, z[ka], o);
      const dl = zl !== null && zr !== null ? (zl - zr) / 1.5 : 0;  // dz per m to the left
      const ds = zf !== null && zb !== null && s[kb] > s[ka] ? (zf - zb) / (s[kb] - s[ka]) : 0;  // dz per m along
      const [nx, ny] = normal[k], tx = ny, ty = -nx;
      // gradient in world xy: ds along the tangent, dl along the left normal
      const gx = ds * tx + dl * nx, gy = ds * ty + dl * ny;
      return up.set(-gx, -gy, 1).normalize();
    };
    const vertex = (k, o, u, v, c) => {
      const [x, y] = xy[k], [nx, ny] = normal[k];
      const h = heightAt(offsets, z[k], o);
      pos.push(x + o * nx, y + o * ny, (h === null ? 0 : h) + LIFT);
      const g = groundNormal(k, o);
      nor.push(g.x, g.y, g.z);
      col.push(c.r, c.g, c.b);
      uv.push(u, v);
      return pos.length / 3 - 1;
    };
    // a quad from station a to b between lateral offsets [oa0, oa1] at a and [ob0, ob1] at b
    const quad = (a, b, oa0, oa1, ob0, ob1, region, v0, v1, ca, cb) => {
      if (oa1 - oa0 < 1e-4 && ob1 - ob0 < 1e-4) return;
      const [u0, u1] = REGION[region];
      const i0 = vertex(a, oa0, u0, v0, ca), i1 = vertex(a, oa1, u1, v0, ca);
      const i2 = vertex(b, ob0, u0, v1, cb), i3 = vertex(b, ob1, u1, v1, cb);
      idx.push(i0, i2, i3, i0, i3, i1);  // offsets grow to the left: counter-clockwise seen from above
    };
    const segments = closed ? n : n - 1;
    for (let a = 0; a < segments; ++a) {
      const b = (a + 1) % n;
      const sa = s[a], sb = b === 0 ? s[n - 1] + Math.hypot(xy[0][0] - xy[n - 1][0], xy[0][1] - xy[n - 1][1]) : s[b];
      if (z[a].every((h) => h === null) || z[b].every((h) => h === null)) continue;
      const ka = kerb[a], kb = kerb[b], ca = surface(a).clone(), cb = surface(b).clone();
      // kerbs (the right edge is -hw), v: 4 m a red and white pair
      quad(a, b, -hw, -hw + ka, -hw, -hw + kb, 'kerb', sa / 4, sb / 4, white, white);
      quad(a, b, hw - ka, hw, hw - kb, hw, 'kerb', sa / 4, sb / 4, white, white);
      const chequer = onLine(sa, sb);
      // edge lines
      for (const side of [-1, 1]) {
        const oa = side * (hw - ka), ob = side * (hw - kb);
        const [a0, a1] = side < 0 ? [oa, oa + LINE] : [oa - LINE, oa], [b0, b1] = side < 0 ? [ob, ob + LINE] : [ob - LINE, ob];
        if (chequer) quad(a, b, a0, a1, b0, b1, 'chequer', 0, 0.02, white, white);
        else quad(a, b, a0, a1, b0, b1, 'paint', 0, 1, white, white);
      }
      // the road between the lines, cut at the bridge's offsets (so it follows the sampled heights)
      const ra0 = -hw + ka + LINE, ra1 = hw - ka - LINE, rb0 = -hw + kb + LINE, rb1 = hw - kb - LINE;
      const lo = Math.max(ra0, rb0), hi = Math.min(ra1, rb1);
      const cuts = offsets.filter((o) => o > lo + 0.05 && o < hi - 0.05);
      const ta = [ra0, ...cuts, ra1], tb = [rb0, ...cuts, rb1];
      for (let j = 0; j + 1 < ta.length; ++j) {
        if (chequer) {
          // squares of about 0.6 m: u across the cut's width, v along
          quad(a, b, ta[j], ta[j + 1], tb[j], tb[j + 1], 'chequer', 0, (sb - sa) / 2.4, white, white);
        } else {
          const w = (ta[j + 1] - ta[j] + tb[j + 1] - tb[j]) / 2;
          quad(a, b, ta[j], ta[j + 1], tb[j], tb[j + 1], 'road', sa / w, sb / w, ca, cb);
        }
      }
    }
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    geo.setAttribute('normal', new THREE.Float32BufferAttribute(nor, 3));
    geo.setAttribute('color', new THREE.Float32BufferAttribute(col, 3));
    geo.setAttribute('uv', new THREE.Float32BufferAttribute(uv, 2));
    geo.setIndex(idx);
    geo.computeBoundingSphere();
    geo.computeBoundingBox();
    return geo;
  }

  // The ribbon's height at (x, y) (a ray from above), or null off it (tests)
  // The ribbon's top height at (x, y), or null off it (tests ask this at
  // thousands of ground-grid nodes: the triangles are indexed once on a
  // 4 m grid in xy, not raycast one by one; the mesh is in world
  // coordinates, untransformed).
  heightAt(x, y) {
    if (!this.mesh) return null;
    const cells = this.cells || (this.cells = indexTriangles(this.mesh.geometry, CELL));
    const list = cells.get(cellKey(Math.floor(x / CELL), Math.floor(y / CELL)));
    if (!list) return null;
    const p = this.mesh.geometry.attributes.position.array, ix = this.mesh.geometry.index ? this.mesh.geometry.index.array : null;
    let best = null;
    for (const t of list) {
      const [a, b, c] = ix ? [ix[3 * t], ix[3 * t + 1], ix[3 * t + 2]] : [3 * t, 3 * t + 1, 3 * t + 2];
      const ax = p[3 * a], ay = p[3 * a + 1], bx = p[3 * b], by = p[3 * b + 1], cx = p[3 * c], cy = p[3 * c + 1];
      const d = (by - cy) * (ax - cx) + (cx - bx) * (ay - cy);
      if (d === 0) continue;
      const u = ((by - cy) * (x - cx) + (cx - bx) * (y - cy)) / d, v = ((cy - ay) * (x - cx) + (ax - cx) * (y - cy)) / d, w = 1 - u - v;
      if (u < -1e-9 || v < -1e-9 || w < -1e-9) continue;
      const z = u * p[3 * a + 2] + v * p[3 * b + 2] + w * p[3 * c + 2];
      if (best === null || z > best) best = z;
    }
    return best;
  }
  clear() {
    if (this.mesh) {
      this.scene.remove(this.mesh);
      this.mesh.geometry.dispose();
      this.mesh.material.dispose();
    }
    this.mesh = null;
    this.track = null;
    this.cells = null;
  }
}
