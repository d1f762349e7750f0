// The session's ground to the horizon, from heights the bridge samples
// through the scenario layer (the page never evaluates H):
//  - near the followed car a fine grid ("ground" messages, 81 x 0.5 m,
//    asked for again as the car moves);
//  - the scene's horizon levels (layout.horizon, sent once: 65 x 65 nodes of
//    4, 16, 64 and 256 m, 256 m to 16 km across, centred on the cars' start);
//  - beyond the coarsest level a flat ring at its edge's mean height out to
//    40 km, where the fog has long hidden it.
// Each coarser mesh discards the fragments under the next finer one (a
// "hole" rectangle in its shader) and every grid hangs a skirt below its
// border, so levels neither fight in depth nor leave cracks.
// Shading: colour by surface, from the friction the bridge sends by node
// (patches and maps) or the scene's contact.friction: asphalt, wet asphalt,
// grass, snow, ice; a heightfield's or a curved ground's own surface (no
// patch there) reads as terrain, grass turning to earth and rock with slope.
// A world-anchored grain texture over it so speed reads as it passes.
import * as THREE from 'three';

// surface classes by Coulomb mu (docs/terrain.md's named surfaces)
export function surfaceOf(mu) {
  if (mu >= 0.8) return 'asphalt';
  if (mu >= 0.52) return 'wet';
  if (mu >= 0.35) return 'grass';
  if (mu >= 0.17) return 'snow';
  return 'ice';
}
export const PALETTE = {
  asphalt: new THREE.Color(0x54565a), wet: new THREE.Color(0x2c3238), grass: new THREE.Color(0x5d7f38),
  snow: new THREE.Color(0xeef2f6), ice: new THREE.Color(0xb6d4e8),
  earth: new THREE.Color(0x7b6a4c), rock: new THREE.Color(0x7d7a74),
};

function grainTexture() {
  const size = 256, c = document.createElement('canvas');
  c.width = c.height = size;
  const g = c.getContext('2d');
  g.fillStyle = '#e0e0e0';
  g.fillRect(0, 0, size, size);
  let seed = 7;
  const rnd = () => ((seed = (seed * 16807) % 2147483647) / 2147483647);
  for (let i = 0; i < 160; ++i) {  // blotches
    const v = 200 + Math.floor(rnd() * 55);
    g.fillStyle = `rgba(${v},${v},${v},0.35)`;
    g.beginPath();
    g.arc(rnd() * size, rnd() * size, 4 + rnd() * 18, 0, 2 * Math.PI);
    g.fill();
  }
  for (let i = 0; i < 9000; ++i) {  // grain
    const v = 160 + Math.floor(rnd() * 95);
    g.fillStyle = `rgb(${v},${v},${v})`;
    g.fillRect(rnd() * size, rnd() * size, 1.5, 1.5);
  }
  const t = new THREE.CanvasTexture(c);
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  t.anisotropy = 4;
  t.colorSpace = THREE.SRGBColorSpace;
  return t;
}
const TILE = 3;  // m of ground per grain tile

// a world-space hash, for colour variation the coarse levels would lack
const hash = (x, y) => {
  const s = Math.sin(x * 0.0137 + y * 0.0213) * 43758.5453 + Math.sin(x * 0.0031 - y * 0.0047) * 1731.7;
  return s - Math.floor(s);
};

// terrain: the ground's own surface is natural ground (not a plane)
function colourAt(out, mu, nz, x, y, natural) {
  if (natural) {
    // grass, earth from 20 degrees, rock from 35
    const slope = Math.acos(Math.min(1, Math.max(-1, nz)));
    out.copy(PALETTE.grass);
    const e = Math.min(1, Math.max(0, (slope - 0.33) / 0.17)), r = Math.min(1, Math.max(0, (slope - 0.58) / 0.15));
    out.lerp(PALETTE.earth, e).lerp(PALETTE.rock, r);
  } else {
    out.copy(PALETTE[surfaceOf(mu)]);
  }
  const k = 0.9 + 0.2 * hash(x, y);
  return out.multiplyScalar(k);
}

function terrainMaterial(grain) {
  // both sides: a coarse level's hovering edge seen from below (a car in a
  // valley) must not show the sky through it
  const material = new THREE.MeshLambertMaterial({ map: grain, vertexColors: true, side: THREE.DoubleSide });
  const hole = { value: new THREE.Vector4(1, 1, -1, -1) };  // empty
  material.userData.hole = hole;
  material.onBeforeCompile = (shader) => {
    shader.uniforms.hole = hole;
    shader.vertexShader = shader.vertexShader
      .replace('#include <common>', '#include <common>\nvarying vec2 vGroundXY;')
      .replace('#include <begin_vertex>', '#include <begin_vertex>\nvGroundXY = (modelMatrix * vec4(transformed, 1.0)).xy;');
    shader.fragmentShader = shader.fragmentShader
      .replace('#include <common>', '#include <common>\nvarying vec2 vGroundXY;\nuniform vec4 hole;')
      .replace('#include <clipping_planes_fragment>', '#include <clipping_planes_fragment>\n'
        + 'if (vGroundXY.x > hole.x && vGroundXY.x < hole.z && vGroundXY.y > hole.y && vGroundXY.y < hole.w) discard;');
  };
  material.customProgramCacheKey = () => 'groundsim-terrain';
  return material;
}

// A grid {x0, y0, n, step, z: [n*n] (null: no surface), mu?: [n*n]} as a
// mesh with a skirt `skirt` m deep; defaultMu where mu is absent or null.
// sink: metres to lower each node by (n * n: the horizon's nodes under a
// race track), or null
function gridGeometry(grid, defaultMu, natural, skirt, sink = null) {
  const { x0, y0, n, step } = grid;
  const z = new Float32Array(n * n);
  let fallback = 0;
  for (const h of grid.z) if (h !== null) { fallback = h; break; }
  for (let k = 0; k < n * n; ++k) {
    const h = grid.z[k];
    if (h === null || h === undefined) z[k] = fallback; else fallback = z[k] = h;
  }
  const border = 4 * (n - 1), count = n * n + border;
  const pos = new Float32Array(count * 3), nor = new Float32Array(count * 3), col = new Float32Array(count * 3),
    uv = new Float32Array(count * 2);
  const c = new THREE.Color(), v = new THREE.Vector3();
  const at = (i, j) => z[Math.min(n - 1, Math.max(0, i)) * n + Math.min(n - 1, Math.max(0, j))];
  const put = (k, i, j, dz) => {
    const x = x0 + j * step, y = y0 + i * step;
    v.set(-(at(i, j + 1) - at(i, j - 1)) / (2 * step), -(at(i + 1, j) - at(i - 1, j)) / (2 * step), 1).normalize();
    pos.set([x, y, z[i * n + j] - dz - (sink ? sink[i * n + j] : 0)], 3 * k);
    nor.set([v.x, v.y, v.z], 3 * k);
    const m = grid.mu && grid.mu[i * n + j] !== null && grid.mu[i * n + j] !== undefined ? grid.mu[i * n + j] : null;
    // a horizon level carries the scene's mu where no patch is: that is the ground's own surface too
    const own = m === null || m === defaultMu;
    colourAt(c, own ? defaultMu : m, v.z, x, y, natural && own);
    col.set([c.r, c.g, c.b], 3 * k);
    uv.set([x / TILE, y / TILE], 2 * k);
  };
  for (let i = 0; i < n; ++i) for (let j = 0; j < n; ++j) put(i * n + j, i, j, 0);
  const idx = [];
  for (let i = 0; i + 1 < n; ++i)
    for (let j = 0; j + 1 < n; ++j) {
      const a = i * n + j, b = a + 1, d = a + n + 1, e = a + n;
      idx.push(a, b, d, a, d, e);
    }
  // the skirt: the border walked once round, each node copied `skirt` below
  const ring = [];
  for (let j = 0; j < n - 1; ++j) ring.push([0, j]);
  for (let i = 0; i < n - 1; ++i) ring.push([i, n - 1]);
  for (let j = n - 1; j > 0; --j) ring.push([n - 1, j]);
  for (let i = n - 1; i > 0; --i) ring.push([i, 0]);
  ring.forEach(([i, j], r) => put(n * n + r, i, j, skirt));
  for (let r = 0; r < border; ++r) {
    const [i, j] = ring[r], [i2, j2] = ring[(r + 1) % border];
    const a = i * n + j, b = i2 * n + j2, a2 = n * n + r, b2 = n * n + (r + 1) % border;
    idx.push(a, a2, b, b, a2, b2);
  }
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
  geo.setAttribute('normal', new THREE.BufferAttribute(nor, 3));
  geo.setAttribute('color', new THREE.BufferAttribute(col, 3));
  geo.setAttribute('uv', new THREE.BufferAttribute(uv, 2));
  geo.setIndex(idx);
  geo.computeBoundingSphere();
  let sum = 0;
  for (const [i, j] of ring) sum += z[i * n + j];
  return { geo, edgeZ: sum / border };
}

const extentOf = (g) => [g.x0, g.y0, g.x0 + g.step * (g.n - 1), g.y0 + g.step * (g.n - 1)];

export class Terrain {
  constructor(scene) {
    this.scene = scene;
    this.grain = grainTexture();
    this.meshes = [];       // the horizon's levels and the far ring
    this.mesh = null;       // the near grid
    this.center = null;     // [x, y] of the near grid shown
    this.extent = 0;
    this.defaultMu = 1;
    this.natural = false;
    this.levels = [];       // extents [x0, y0, x1, y1] of the horizon levels, finest first
  }
  // A race track's stations (layout.track): the horizon's nodes within its
  // half width plus a step of it are lowered by 0.1 m + 5 % of their step,
  // so a coarse level's straight lines between samples a step apart never
  // rise through the ribbon drawn on the exact heights (track.js); the near
  // grid's 0.5 m samples stay as they are (the ribbon is 3 cm above them).
  setTrack(track) {
    this.sink = null;
    if (!track || !track.xy || track.xy.length < 2) return;
    const hw = track.half_width;
    // per grid: each station marks the nodes within reach of it (a few
    // per station and level: cheap on a 2 km stage)
    this.sink = (grid) => {
      const { x0, y0, n, step } = grid, out = new Float32Array(n * n), reach = hw + step + 1, depth = 0.1 + 0.05 * step;
      const r = Math.ceil(reach / step);
      for (const [x, y] of track.xy) {
        const cj = Math.round((x - x0) / step), ci = Math.round((y - y0) / step);
        if (ci < -r || cj < -r || ci >= n + r || cj >= n + r) continue;
        for (let i = Math.max(0, ci - r); i <= Math.min(n - 1, ci + r); ++i)
          for (let j = Math.max(0, cj - r); j <= Math.min(n - 1, cj + r); ++j)
            if ((x0 + j * step - x) ** 2 + (y0 + i * step - y) ** 2 < reach * reach) out[i * n + j] = depth;
      }
      return out;
    };
  }
  // layout: the session's (friction, ground kind, horizon levels), or null
  setLayout(layout) {
    this.clear();
    if (!layout) return;
    this.setTrack(layout.track);
    this.defaultMu = typeof layout.friction === 'number' ? layout.friction : 1;
    this.natural = !['plane', 'incline'].includes(layout.ground);
    this.setHorizon(layout.horizon || []);
  }
  setHorizon(levels) {
    for (const m of this.meshes) { this.scene.remove(m); m.geometry.dispose(); m.material.dispose(); }
    this.meshes = [];
    this.levels = levels.map(extentOf);
    let edgeZ = 0;
    levels.forEach((g, l) => {
      const built = gridGeometry(g, this.defaultMu, this.natural, 2 * g.step, this.sink ? this.sink(g) : null);
      edgeZ = built.edgeZ;
      const m = new THREE.Mesh(built.geo, terrainMaterial(this.grain));
      m.receiveShadow = l === 0;
      m.name = `horizon-${l}`;
      if (l > 0) this.setHole(m, levels[l - 1]);
      this.scene.add(m);
      this.meshes.push(m);
    });
    if (levels.length) {
      // the far ring: a plane at the coarsest level's edge height
      const last = levels[levels.length - 1], [x0, y0, x1, y1] = extentOf(last), R = 40000;
      const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
      const far = gridGeometry({ x0: cx - R, y0: cy - R, n: 3, step: R, z: new Array(9).fill(edgeZ) },
        this.defaultMu, this.natural, 0).geo;
      const m = new THREE.Mesh(far, terrainMaterial(this.grain));
      m.name = 'horizon-far';
      this.setHole(m, last);
      this.scene.add(m);
      this.meshes.push(m);
    }
    this.holeUnderNear();
  }
  // m's fragments inside the finer grid g (less a step at its border, where
  // the finer grid's skirt covers the seam) are not drawn
  setHole(m, g) {
    const [x0, y0, x1, y1] = extentOf(g), s = g.step;
    m.material.userData.hole.value.set(x0 + s, y0 + s, x1 - s, y1 - s);
  }
  holeUnderNear() {
    if (this.meshes.length && this.grid) this.setHole(this.meshes[0], this.grid);
  }
  // the near grid: {x0, y0, n, step, z: [n*n], null where no surface, mu?}
  show(grid) {
    const { geo } = gridGeometry(grid, this.defaultMu, this.natural, 1.0);
    if (this.mesh) { this.scene.remove(this.mesh); this.mesh.geometry.dispose(); }
    else this.material = terrainMaterial(this.grain);
    this.mesh = new THREE.Mesh(geo, this.material);
    this.mesh.name = 'ground-near';
    this.mesh.receiveShadow = true;
    this.scene.add(this.mesh);
    this.grid = grid;
    this.center = [grid.x0 + grid.step * (grid.n - 1) / 2, grid.y0 + grid.step * (grid.n - 1) / 2];
    this.extent = grid.step * (grid.n - 1);
    this.holeUnderNear();
  }
  // True when (x, y) has moved a quarter of the near grid from its centre.
  needsRefresh(x, y) {
    if (!this.center) return true;
    return Math.max(Math.abs(x - this.center[0]), Math.abs(y - this.center[1])) > this.extent / 4;
  }
  // Stand-in when the page has no scene for the session (a replay, a
  // session whose scenario did not build here): flat ground at height z.
  flat(cx, cy, z, mu = 1) {
    this.defaultMu = mu;
    this.natural = false;
    const level = (n, step) => ({ x0: Math.round(cx / step) * step - step * (n - 1) / 2,
      y0: Math.round(cy / step) * step - step * (n - 1) / 2, n, step, z: new Array(n * n).fill(z) });
    this.setHorizon([level(17, 16), level(17, 256)]);
    this.show(level(41, 1));
  }
  allMeshes() { return (this.mesh ? [this.mesh] : []).concat(this.meshes); }
  // Height of the drawn ground at (x, y) (a ray from above; 0 where none)
  heightAt(x, y) {
    const ray = new THREE.Raycaster(new THREE.Vector3(x, y, 1e5), new THREE.Vector3(0, 0, -1));
    const hit = ray.intersectObjects(this.allMeshes(), false)[0];
    return hit ? hit.point.z : 0;
  }
  clear() {
    this.sink = null;
    this.setHorizon([]);
    if (this.mesh) { this.scene.remove(this.mesh); this.mesh.geometry.dispose(); this.mesh = null; }
    this.center = null;
    this.grid = null;
  }
}
