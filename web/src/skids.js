// Tyre marks where the state shows a wheel sliding: the state's slip (m/s
// of the contact point over the ground) above SLIDE_MS, or a road car's
// slip ratio above 0.25 or slip angle above 0.2 rad, while the wheel
// touches. One mesh of quads in a ring buffer (the oldest marks give way),
// laid a hair above the ground.
import * as THREE from 'three';

const MAX = 3000, WIDTH = 0.2, SLIDE_MS = 1.5;

export function sliding(v, car, i) {
  if (v.contact && v.contact[i] === false) return false;
  if (car && car.slip_ratio) return Math.abs(car.slip_ratio[i] || 0) > 0.25 || Math.abs(car.slip_angle[i] || 0) > 0.2;
  return Math.abs((v.slip && v.slip[i]) || 0) > SLIDE_MS;
}

export class SkidMarks {
  constructor(scene) {
    this.scene = scene;
    this.pos = new Float32Array(MAX * 4 * 3);
    const idx = new Uint32Array(MAX * 6);
    for (let k = 0; k < MAX; ++k) idx.set([4 * k, 4 * k + 1, 4 * k + 2, 4 * k + 2, 4 * k + 1, 4 * k + 3], 6 * k);
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(this.pos, 3).setUsage(THREE.DynamicDrawUsage));
    g.setIndex(new THREE.BufferAttribute(idx, 1));
    this.mesh = new THREE.Mesh(g, new THREE.MeshBasicMaterial({ color: 0x111111, transparent: true, opacity: 0.55,
      depthWrite: false, polygonOffset: true, polygonOffsetFactor: -2, polygonOffsetUnits: -2 }));
    this.mesh.frustumCulled = false;
    this.mesh.name = 'skidmarks';
    scene.add(this.mesh);
    this.next = 0;
    this.count = 0;   // quads laid since the last reset
    this.last = new Map();  // "car:wheel" -> the previous point, while sliding
    this.p = new THREE.Vector3();
  }
  reset() {
    this.pos.fill(0);
    this.mesh.geometry.attributes.position.needsUpdate = true;
    this.last.clear();
    this.count = 0;
  }
  // vehicle: the drawn Vehicle (its wheels' contact points); v: its state; car: its road-car state or null
  update(key, vehicle, v, car) {
    for (let i = 0; i < vehicle.wheels.length; ++i) {
      const id = `${key}:${i}`;
      if (!sliding(v, car, i)) { this.last.delete(id); continue; }
      const p = vehicle.contactPoint(i, this.p).clone();
      p.z += 0.02;
      const prev = this.last.get(id);
      this.last.set(id, p);
      if (!prev) continue;
      const d = p.distanceTo(prev);
      if (d < 0.15) { this.last.set(id, prev); continue; }
      if (d > 3) continue;  // a reset or a jump: no streak across it
      const sx = -(p.y - prev.y) / d * WIDTH / 2, sy = (p.x - prev.x) / d * WIDTH / 2;
      this.pos.set([prev.x + sx, prev.y + sy, prev.z, prev.x - sx, prev.y - sy, prev.z,
        p.x + sx, p.y + sy, p.z, p.x - sx, p.y - sy, p.z], 12 * this.next);
      this.next = (this.next + 1) % MAX;
      this.count++;
      this.mesh.geometry.attributes.position.needsUpdate = true;
    }
  }
}
