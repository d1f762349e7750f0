// The scenario's objects (layout.objects, placed by the bridge through the
// scenario layer: an on_ground object already stands on the ground), drawn
// as what they stand for: a static box as a concrete wall or barrier (a low
// one as a red and white kerb), a box with mass as a crate, a cone as an
// orange traffic cone with a white band, other shapes in plain materials.
// Objects with mass move with the session's contact states (by name).
// Static objects are baked into one mesh per material (a circuit's 38 walls
// and kerbs, a stage's 24 cones: 2 draw calls each with the shadow pass
// instead of 76 or 96); each keeps an invisible mesh of its own for
// describe() and its name.
import * as THREE from 'three';
import { RoundedBoxGeometry } from 'three/examples/jsm/geometries/RoundedBoxGeometry.js';
import { mergeGeometries } from 'three/examples/jsm/utils/BufferGeometryUtils.js';

function canvasTexture(draw, size = 128) {
  const c = document.createElement('canvas');
  c.width = c.height = size;
  draw(c.getContext('2d'), size);
  const t = new THREE.CanvasTexture(c);
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  t.colorSpace = THREE.SRGBColorSpace;
  return t;
}

// concrete: grey with speckles; a kerb: red and white blocks
let concreteTex = null, kerbTex = null;
const concrete = () => concreteTex || (concreteTex = canvasTexture((g, n) => {
  g.fillStyle = '#a7a49c';
  g.fillRect(0, 0, n, n);
  for (let i = 0; i < 900; ++i) {
    const v = 120 + Math.floor(Math.random() * 80);
    g.fillStyle = `rgb(${v},${v - 2},${v - 6})`;
    g.fillRect(Math.random() * n, Math.random() * n, 2, 2);
  }
  g.strokeStyle = '#77746d';
  g.lineWidth = 3;
  g.strokeRect(0, 0, n, n);  // the joints between precast sections
}));
const kerb = () => kerbTex || (kerbTex = canvasTexture((g, n) => {
  g.fillStyle = '#c8322a';
  g.fillRect(0, 0, n / 2, n);
  g.fillStyle = '#f2f2f2';
  g.fillRect(n / 2, 0, n / 2, n);
}));

const MATS = {};
const mat = (key, make) => MATS[key] || (MATS[key] = make());

// Box faces map their uv 0..1: repeat the texture once per `tile` metres
// along the box's longest horizontal side.
function tiled(tex, length, tile) {
  const t = tex.clone();
  t.needsUpdate = true;
  t.repeat.set(Math.max(1, Math.round(length / tile)), 1);
  return t;
}
// the material a static object's part is baked with, by kind; its map's repeat goes into the uvs
const BAKED = {
  kerb: () => mat('baked-kerb', () => new THREE.MeshLambertMaterial({ map: kerb() })),
  concrete: () => mat('baked-concrete', () => new THREE.MeshLambertMaterial({ map: concrete() })),
};

function boxMesh(o) {
  const [sx, sy, sz] = o.size;
  const r = Math.min(o.rounding || 0, 0.5 * Math.min(sx, sy, sz));
  const geo = r > 1e-3 ? new RoundedBoxGeometry(sx, sy, sz, 2, r) : new THREE.BoxGeometry(sx, sy, sz);
  let material, kind;
  if (!o.static) {
    kind = 'crate';
    material = mat('crate', () => new THREE.MeshLambertMaterial({ color: 0xb5854b }));
  } else if (sz < 0.35) {
    kind = 'kerb';
    material = new THREE.MeshLambertMaterial({ map: tiled(kerb(), Math.max(sx, sy), 1.0) });
    material.userData.baked = 'kerb';
  } else {
    kind = sz > 1.6 ? 'wall' : 'barrier';
    material = new THREE.MeshLambertMaterial({ map: tiled(concrete(), Math.max(sx, sy), 2.0) });
    material.userData.baked = 'concrete';
  }
  const m = new THREE.Mesh(geo, material);
  m.userData.kind = kind;
  return m;
}

// A frustum along local z: bottom radius r0 at -h/2, top radius r1 at +h/2.
function frustum(r0, r1, h, z0 = -h / 2, z1 = h / 2) {
  const at = (z) => r0 + (r1 - r0) * ((z + h / 2) / h);
  const g = new THREE.CylinderGeometry(at(z1), at(z0), z1 - z0, 24, 1);
  g.rotateX(Math.PI / 2);  // three's y axis onto local z
  g.translate(0, 0, (z0 + z1) / 2);
  return g;
}

function coneMesh(o) {
  const h = o.height, r0 = o.radius, r1 = o.top_radius || 0;
  const g = new THREE.Group();
  const orange = mat('cone', () => new THREE.MeshLambertMaterial({ color: 0xff6a13 }));
  const white = mat('band', () => new THREE.MeshLambertMaterial({ color: 0xf5f5f5 }));
  g.add(new THREE.Mesh(frustum(r0, r1, h), orange));
  // the reflective band, a hair proud of the cone, from 55 % to 75 % of its height
  const band = new THREE.Mesh(frustum(r0 * 1.02, r1 * 1.02 + 0.005, h, -h / 2 + 0.55 * h, -h / 2 + 0.75 * h), white);
  g.add(band);
  g.userData.kind = 'cone';
  return g;
}

function plainMesh(o) {
  const color = o.static ? 0x8a8f96 : 0x3f7fbf;
  let geo;
  if (o.shape === 'sphere') geo = new THREE.SphereGeometry(o.radius, 24, 16);
  else if (o.shape === 'cylinder') geo = frustum(o.radius, o.radius, o.height);
  else {  // capsule: height end to end
    geo = new THREE.CapsuleGeometry(o.radius, Math.max(0, o.height - 2 * o.radius), 6, 20);
    geo.rotateX(Math.PI / 2);
  }
  const m = new THREE.Mesh(geo, new THREE.MeshLambertMaterial({ color }));
  m.userData.kind = o.shape;
  return m;
}

export function objectMesh(o) {
  const m = o.shape === 'box' ? boxMesh(o) : o.shape === 'cone' ? coneMesh(o) : plainMesh(o);
  m.traverse((c) => { if (c.isMesh) { c.castShadow = true; c.receiveShadow = true; } });
  m.name = o.name;
  return m;
}

export class SceneObjects {
  constructor(scene, list) {
    this.scene = scene;
    this.byName = new Map();
    const baked = new Map();  // material -> geometries in world coordinates
    this.meshes = (list || []).map((o) => {
      const m = objectMesh(o);
      m.position.set(...o.p);
      m.quaternion.set(o.q[1], o.q[2], o.q[3], o.q[0]);
      m.userData.layout = o;
      scene.add(m);
      this.byName.set(o.name, m);
      if (o.static) {
        m.updateMatrixWorld(true);
        m.traverse((c) => {
          if (!c.isMesh) return;
          let g = c.geometry.index ? c.geometry.toNonIndexed() : c.geometry.clone();
          g.applyMatrix4(c.matrixWorld);
          for (const name of Object.keys(g.attributes)) if (!['position', 'normal', 'uv'].includes(name)) g.deleteAttribute(name);
          let material = c.material;
          const kind = material.userData.baked;
          if (kind) {
            const r = material.map.repeat, uv = g.attributes.uv;
            for (let i = 0; i < uv.count; ++i) uv.setXY(i, uv.getX(i) * r.x, uv.getY(i) * r.y);
            material = BAKED[kind]();
          }
          if (!baked.has(material)) baked.set(material, []);
          baked.get(material).push(g);
        });
        m.visible = false;
      }
      return m;
    });
    this.baked = [];
    for (const [material, geos] of baked) {
      const merged = new THREE.Mesh(mergeGeometries(geos, false), material);
      merged.name = 'static-objects';
      merged.castShadow = merged.receiveShadow = true;
      scene.add(merged);
      this.baked.push(merged);
      for (const g of geos) g.dispose();
    }
  }
  // objects: the interpolated poses of the objects with mass (contact states)
  update(objects) {
    if (!objects) return;
    for (const o of objects) {
      const m = this.byName.get(o.name);
      if (!m || m.userData.layout.static) continue;
      m.position.set(...o.p);
      m.quaternion.set(o.q[1], o.q[2], o.q[3], o.q[0]);
    }
  }
  // what the page shows, for tests: name, kind, position
  describe() {
    return this.meshes.map((m) => ({ name: m.name, kind: m.userData.kind, p: m.position.toArray() }));
  }
  dispose() {
    for (const m of this.meshes) this.scene.remove(m);
    for (const m of this.baked || []) { this.scene.remove(m); m.geometry.dispose(); }
    this.meshes = [];
    this.baked = [];
    this.byName.clear();
  }
}
