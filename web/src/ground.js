// The session's ground as a mesh: height grids sampled by the bridge through
// the scenario layer (the page never evaluates H), lit so slopes read, with
// a 1 m grid texture in world coordinates so speed reads as the lines pass.
import * as THREE from 'three';

function gridTexture() {
  const size = 256, c = document.createElement('canvas');
  c.width = c.height = size;
  const g = c.getContext('2d');
  g.fillStyle = '#6f8f5a';
  g.fillRect(0, 0, size, size);
  g.strokeStyle = '#2f3f28';
  g.lineWidth = 6;
  g.strokeRect(0, 0, size, size);
  g.strokeStyle = '#4d6640';
  g.lineWidth = 2;
  g.beginPath();
  g.moveTo(size / 2, 0); g.lineTo(size / 2, size);
  g.moveTo(0, size / 2); g.lineTo(size, size / 2);
  g.stroke();
  const t = new THREE.CanvasTexture(c);
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  t.anisotropy = 4;
  t.colorSpace = THREE.SRGBColorSpace;
  return t;
}

export class GroundMesh {
  constructor(scene) {
    this.scene = scene;
    this.material = new THREE.MeshLambertMaterial({ map: gridTexture(), side: THREE.DoubleSide });
    this.mesh = null;
    this.center = null;   // [x, y] of the grid shown
    this.extent = 0;
  }
  // grid: {x0, y0, n, step, z: [n*n], null where no surface}
  show(grid) {
    const { x0, y0, n, step, z } = grid;
    const pos = new Float32Array(n * n * 3), uv = new Float32Array(n * n * 2);
    let fallback = 0;
    for (const h of z) if (h !== null) { fallback = h; break; }
    for (let i = 0; i < n; ++i)
      for (let j = 0; j < n; ++j) {
        const k = i * n + j, x = x0 + j * step, y = y0 + i * step;
        let h = z[k];
        if (h === null) h = fallback; else fallback = h;
        pos.set([x, y, h], 3 * k);
        uv.set([x, y], 2 * k);  // one texture tile per metre
      }
    const idx = [];
    for (let i = 0; i + 1 < n; ++i)
      for (let j = 0; j + 1 < n; ++j) {
        const a = i * n + j, b = a + 1, c = a + n, d = c + 1;
        idx.push(a, b, d, a, d, c);
      }
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    geo.setAttribute('uv', new THREE.BufferAttribute(uv, 2));
    geo.setIndex(idx);
    geo.computeVertexNormals();
    if (this.mesh) { this.scene.remove(this.mesh); this.mesh.geometry.dispose(); }
    this.mesh = new THREE.Mesh(geo, this.material);
    this.mesh.receiveShadow = true;
    this.scene.add(this.mesh);
    this.center = [x0 + step * (n - 1) / 2, y0 + step * (n - 1) / 2];
    this.extent = step * (n - 1);
  }
  // True when (x, y) has moved a quarter of the grid from its centre.
  needsRefresh(x, y) {
    if (!this.center) return true;
    return Math.max(Math.abs(x - this.center[0]), Math.abs(y - this.center[1])) > this.extent / 4;
  }
  // Stand-in when the bridge could not build the session's scene (a replay
  // without its scenario): a flat grid at height z, labelled as such in the HUD.
  flat(cx, cy, z) {
    const n = 41, step = 1, zs = new Array(n * n).fill(z);
    this.show({ x0: cx - 20, y0: cy - 20, n, step, z: zs });
  }
}
