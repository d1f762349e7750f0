/* global GROUNDSIM_FULL_LOCK */  // the full lock (rad), defined at bundle time from kFullLockRad (web/CMakeLists.txt)
// One vehicle as drawn: a low-poly body for its kind (a road car as a sedan
// with cabin, glass, head and brake lights; the report's car and other
// multi-wheel vehicles as a rounded chassis tub), in the car's own colour
// with its name above it; wheels that turn (spin integrated from the state's
// wheel_spin), steer and ride on their suspension. The report's figure 1
// (every mass point and spring of the model, from the layout the bridge
// built through the scenario layer) is drawn over it on request (stage.js's
// figure, key F). Suspension: each wheel is drawn raised by its deflection N / k (k:
// the radial stiffness of its coupling to the body), to scale; a road car's
// wheels ("strut" in the layout) by the suspension travel its car state
// reports.
import * as THREE from 'three';
import { mergeGeometries } from 'three/examples/jsm/utils/BufferGeometryUtils.js';
import { RoundedBoxGeometry } from 'three/examples/jsm/geometries/RoundedBoxGeometry.js';

const UP = new THREE.Vector3(0, 0, 1), Y = new THREE.Vector3(0, 1, 0);

// The report's car, for sessions whose scenario is unknown (a replay).
export function defaultLayout(name) {
  const wheel = (x, y, steer) => ({ offset: [x, y, 0], rotation: [1, 0, 0, 0], axis: [0, 1, 0], radius: 1,
    steerable: steer, max_steer: GROUNDSIM_FULL_LOCK, pivot: [x, y, 0], radial_stiffness: 0 });
  return { name, lone_wheel: false, wheels: [wheel(1.5, 1, true), wheel(1.5, -1, true), wheel(-1.5, 1, false), wheel(-1.5, -1, false)],
    points: [], springs: [], body_min: [-1.5, -1.25, 0], body_max: [1.5, 1.25, 0] };
}

// A sedan of configs/sedan.json's size (wheelbase 2.7 m, track 1.55 m,
// wheels 0.32 m, centre of mass 0.55 m up), for a replayed road car whose
// scenario the page does not have.
export function sedanLayout(name) {
  const hubZ = 0.32 - 0.55, half = 0.775;
  const wheel = (x, y, front) => ({ offset: [x, y, hubZ], rotation: [1, 0, 0, 0], axis: [0, 1, 0], radius: 0.32,
    steerable: front, max_steer: front ? GROUNDSIM_FULL_LOCK : 0, pivot: [x, y, hubZ], radial_stiffness: 0, strut: true });
  return { name, lone_wheel: false, road_car: true, mass: 1500,
    wheels: [wheel(1.2, half, true), wheel(1.2, -half, true), wheel(-1.5, half, false), wheel(-1.5, -half, false)],
    points: [], springs: [], body_min: [-2.3, -half - 0.1, hubZ + 0.05], body_max: [2.1, half + 0.1, hubZ + 1.1] };
}

// a side profile [[x, z], ...] extruded across the car, `width` wide, centred on y = 0
function extruded(profile, width, bevel) {
  const shape = new THREE.Shape(profile.map(([x, z]) => new THREE.Vector2(x, z)));
  const g = new THREE.ExtrudeGeometry(shape, { depth: width - 2 * bevel, bevelEnabled: bevel > 0,
    bevelThickness: bevel, bevelSize: bevel, bevelSegments: 2, curveSegments: 1 });
  g.rotateX(Math.PI / 2);
  g.translate(0, (width - 2 * bevel) / 2, 0);
  return g;
}
const box = (sx, sy, sz, x, y, z) => new THREE.BoxGeometry(sx, sy, sz).translate(x, y, z);

const shared = {};
const once = (key, make) => shared[key] || (shared[key] = make());

// The sedan over the layout's body box: lower body, glasshouse, roof,
// bumpers, head and tail lights. Returns {group, tail (material)}.
function sedanBody(lo, hi, hubZ, r, color) {
  const xr = lo.x, xf = hi.x, W = hi.y - lo.y, L = xf - xr;
  const zb = hubZ - r + 0.17, belt = hubZ + 0.42, roof = hi.z;
  const paint = new THREE.MeshLambertMaterial({ color });
  const group = new THREE.Group();
  const lower = extruded([[xr + 0.12, zb], [xf - 0.18, zb], [xf, zb + 0.2], [xf - 0.04, belt - 0.1],
    [xf - 0.22 * L, belt], [xr + 0.06 * L, belt + 0.03], [xr, belt - 0.06], [xr, zb + 0.14]], W, 0.05);
  const body = new THREE.Mesh(lower, paint);
  const aBase = xf - 0.24 * L, aTop = xf - 0.4 * L, cTop = xr + 0.3 * L, cBase = xr + 0.14 * L;
  const glass = new THREE.Mesh(extruded([[cBase, belt], [aBase, belt], [aTop, roof - 0.05], [cTop, roof - 0.05]], W - 0.16, 0.03),
    once('glass', () => new THREE.MeshLambertMaterial({ color: 0x1d2833, emissive: 0x0a1420 })));
  const top = new THREE.Mesh(extruded([[cTop - 0.04, roof - 0.07], [aTop + 0.04, roof - 0.07], [aTop + 0.01, roof], [cTop, roof]], W - 0.14, 0.02), paint);
  const trim = new THREE.Mesh(mergeGeometries([box(0.12, W - 0.05, 0.16, xf - 0.03, 0, zb + 0.1), box(0.12, W - 0.05, 0.16, xr + 0.03, 0, zb + 0.1),
    box(0.6 * L, 0.04, 0.1, (xr + xf) / 2, W / 2, zb + 0.06), box(0.6 * L, 0.04, 0.1, (xr + xf) / 2, -W / 2, zb + 0.06)]),
  once('trim', () => new THREE.MeshLambertMaterial({ color: 0x1e1f22 })));
  // lamps proud of the bevelled body (5 cm beyond its profile)
  const lz = belt - 0.16, ly = W / 2 - 0.22;
  const heads = new THREE.Mesh(mergeGeometries([box(0.1, 0.34, 0.1, xf - 0.02, ly, lz), box(0.1, 0.34, 0.1, xf - 0.02, -ly, lz)]),
    once('head', () => new THREE.MeshLambertMaterial({ color: 0xfff6e0, emissive: 0xfff2d0, emissiveIntensity: 0.6 })));
  const tail = new THREE.MeshLambertMaterial({ color: 0x6a0c0c, emissive: 0xff1a10, emissiveIntensity: 0.15 });
  const tails = new THREE.Mesh(mergeGeometries([box(0.1, 0.36, 0.13, xr - 0.02, ly, lz + 0.04), box(0.1, 0.36, 0.13, xr - 0.02, -ly, lz + 0.04)]), tail);
  body.name = 'body'; glass.name = 'glass'; top.name = 'roof'; heads.name = 'headlights'; tails.name = 'brakelights'; trim.name = 'trim';
  group.add(body, glass, top, trim, heads, tails);
  return { group, tail };
}

// The report's car and other wheeled models: a rounded tub over the axle
// points, with small red lamps at the back for braking.
function tubBody(lo, hi, r, color) {
  const group = new THREE.Group();
  const dims = new THREE.Vector3().subVectors(hi, lo).max(new THREE.Vector3(0.2, 0.2, 0.35 * r));
  const body = new THREE.Mesh(new RoundedBoxGeometry(dims.x, dims.y, dims.z, 2, Math.min(0.15, 0.3 * Math.min(dims.x, dims.y, dims.z))),
    new THREE.MeshLambertMaterial({ color }));
  body.position.copy(lo).add(hi).multiplyScalar(0.5).add(new THREE.Vector3(0, 0, 0.1 * r));
  body.name = 'body';
  const tail = new THREE.MeshLambertMaterial({ color: 0x6a0c0c, emissive: 0xff1a10, emissiveIntensity: 0.15 });
  const s = 0.12 * dims.y, x = body.position.x - dims.x / 2 - 0.01, z = body.position.z;
  const tails = new THREE.Mesh(mergeGeometries([box(0.04, s, s, x, dims.y * 0.35, z), box(0.04, s, s, x, -dims.y * 0.35, z)]), tail);
  tails.name = 'brakelights';
  group.add(body, tails);
  return { group, tail };
}

// A wheel of radius r and width w along three's y: tyre and a rim with spokes.
function wheelMeshes(r, w) {
  const tyre = new THREE.Mesh(new THREE.CylinderGeometry(r, r, w, 24, 1), once('tyre', () => new THREE.MeshLambertMaterial({ color: 0x1c1c1c })));
  const parts = [new THREE.CylinderGeometry(0.62 * r, 0.62 * r, w + 0.01, 20, 1)];
  for (let k = 0; k < 5; ++k) parts.push(new THREE.BoxGeometry(0.12 * r, w + 0.03, 1.2 * r).rotateY((k * Math.PI) / 5));
  const rim = new THREE.Mesh(mergeGeometries(parts), once('rim', () => new THREE.MeshLambertMaterial({ color: 0xb8bcc2 })));
  tyre.castShadow = true;
  return [tyre, rim];
}

function label(text, color) {
  const c = document.createElement('canvas');
  c.width = 256; c.height = 64;
  const g = c.getContext('2d');
  g.fillStyle = 'rgba(16,20,26,0.75)';
  g.beginPath();
  g.roundRect(2, 8, 252, 48, 12);
  g.fill();
  g.fillStyle = `#${new THREE.Color(color).getHexString()}`;
  g.fillRect(14, 22, 20, 20);
  g.fillStyle = '#f2f2f2';
  g.textBaseline = 'middle';
  const shown = text.length > 18 ? `${text.slice(0, 17)}…` : text;
  let px = 28;
  do g.font = `600 ${px}px system-ui, sans-serif`; while (g.measureText(shown).width > 200 && --px > 12);
  g.fillText(shown, 44, 33);
  const t = new THREE.CanvasTexture(c);
  t.colorSpace = THREE.SRGBColorSpace;
  const s = new THREE.Sprite(new THREE.SpriteMaterial({ map: t, sizeAttenuation: false, depthWrite: false, fog: false }));
  s.scale.set(0.16, 0.04, 1);  // of the view's height
  s.center.set(0.5, 0);
  s.renderOrder = 10;
  s.name = 'label';
  return s;
}

export class Vehicle {
  // name: shown above the car ('' for none)
  constructor(scene, layout, color, name = layout.name) {
    this.layout = layout;
    this.scene = scene;
    this.color = color;
    this.root = new THREE.Group();
    scene.add(this.root);
    const lo = new THREE.Vector3(...layout.body_min), hi = new THREE.Vector3(...layout.body_max);
    const r = layout.wheels.length ? layout.wheels[0].radius : 0.5;
    this.size = Math.max(hi.x - lo.x, hi.y - lo.y, 2 * r, 0.5);
    this.kind = layout.road_car ? 'sedan' : layout.lone_wheel ? 'wheel' : 'tub';
    this.tail = null;
    this.brakeLit = false;
    if (this.kind !== 'wheel') {
      const hubZ = layout.wheels.length ? layout.wheels[0].offset[2] : lo.z;
      const { group, tail } = this.kind === 'sedan' ? sedanBody(lo, hi, hubZ, r, color) : tubBody(lo, hi, r, color);
      group.traverse((m) => { if (m.isMesh) { m.castShadow = true; } });
      group.name = this.kind;
      this.body = group;
      this.tail = tail;
      this.root.add(group);
    }
    this.top = Math.max(hi.z, lo.z + 2 * r);
    this.wheels = layout.wheels.map((w) => {
      const pivot = new THREE.Group();        // at the steering pivot, turns about the body's z
      const frame = new THREE.Group();        // the wheel's rest frame relative to the body
      const spin = new THREE.Group();         // turns about the wheel's axle
      pivot.position.set(...w.pivot);
      frame.position.set(w.offset[0] - w.pivot[0], w.offset[1] - w.pivot[1], w.offset[2] - w.pivot[2]);
      frame.quaternion.set(w.rotation[1], w.rotation[2], w.rotation[3], w.rotation[0]);
      const axis = new THREE.Vector3(...w.axis).normalize();
      const align = new THREE.Group();        // cylinder's y onto the axle
      align.quaternion.setFromUnitVectors(Y, axis);
      const width = Math.max(0.15, layout.road_car ? 0.65 * w.radius : 0.25 * w.radius);
      align.add(...wheelMeshes(w.radius, width));
      spin.add(align);
      frame.add(spin);
      pivot.add(frame);
      this.root.add(pivot);
      return { w, pivot, frame, spin, axis, angle: 0, lift: 0 };
    });
    // figure 1: points and springs, in body coordinates, rebuilt every frame they are shown
    const np = layout.points.length;
    this.pointPos = new Float32Array(np * 3);
    const pg = new THREE.BufferGeometry();
    pg.setAttribute('position', new THREE.BufferAttribute(this.pointPos, 3));
    this.points = new THREE.Points(pg, new THREE.PointsMaterial({ color: 0xffe066, size: Math.max(0.06, 0.06 * r) }));
    const sg = new THREE.BufferGeometry();
    this.springPos = new Float32Array(layout.springs.length * 6);
    sg.setAttribute('position', new THREE.BufferAttribute(this.springPos, 3));
    this.springs = new THREE.LineSegments(sg, new THREE.LineBasicMaterial({ color: 0x66ccff, transparent: true, opacity: 0.8, depthTest: false }));
    this.points.material.depthTest = false;
    this.points.renderOrder = this.springs.renderOrder = 5;
    this.points.frustumCulled = this.springs.frustumCulled = false;
    this.root.add(this.points, this.springs);
    this.setFigure(false);
    const front = layout.wheels.filter((w) => w.steerable), rear = layout.wheels.filter((w) => !w.steerable);
    this.wheelbase = front.length && rear.length ? Math.abs(front[0].offset[0] - rear[0].offset[0]) : 0;
    this.steer = 0;
    this.label = name ? label(name, color) : null;
    if (this.label) scene.add(this.label);
    this.name = name;
    this.color = color;
    this.scene = scene;
  }

  // The name shown above the car (a player's, once the lobby names them)
  setName(name) {
    if (name === this.name) return;
    const at = this.label ? this.label.position.clone() : null;
    if (this.label) { this.scene.remove(this.label); this.label.material.map.dispose(); this.label.material.dispose(); }
    this.name = name;
    this.label = name ? label(name, this.color) : null;
    if (this.label) { if (at) this.label.position.copy(at); this.scene.add(this.label); }
  }

  // The report's figure 1 over the body (points and springs), the body
  // see-through under it.
  setFigure(on) {
    this.figure = on && this.layout.points.length > 0;
    this.points.visible = this.springs.visible = this.figure;
    if (this.body) this.body.traverse((m) => {
      if (!m.isMesh || m.name === 'brakelights') return;
      m.material.transparent = this.figure;
      m.material.opacity = this.figure ? 0.35 : 1;
    });
  }

  // v: one interpolated vehicle of a state; dt: s of sim time since the last
  // frame; steer: rad commanded (own car), or null to estimate from the motion;
  // car: the newest road-car state of this vehicle (travel, steer_angle) or
  // null; braking: true/false when known (own controls), null: from car.brake
  update(v, dt, steer, car = null, braking = null) {
    this.root.position.set(...v.p);
    this.root.quaternion.set(v.q[1], v.q[2], v.q[3], v.q[0]);
    if (this.label) this.label.position.set(v.p[0], v.p[1], v.p[2] + this.top + 0.35);
    if (braking === null) braking = !!(car && car.brake > 0.05);
    this.brakeLit = braking;
    if (this.tail) this.tail.emissiveIntensity = braking ? 3.0 : 0.15;
    if (car && Number.isFinite(car.steer_angle)) steer = car.steer_angle;
    else if (steer === null) {
      // a spectator does not know the command: the angle of a bicycle model
      // turning at the body's yaw rate, while moving
      const up = UP.clone().applyQuaternion(this.root.quaternion);
      const yawRate = v.w[0] * up.x + v.w[1] * up.y + v.w[2] * up.z;
      steer = Math.abs(v.speed) > 0.5 && this.wheelbase > 0 ? Math.atan(this.wheelbase * yawRate / v.speed) : this.steer;
    }
    this.steer = steer;
    const m = new THREE.Matrix4();
    this.wheels.forEach((wh, i) => {
      const max = wh.w.max_steer || 0;
      const a = wh.w.steerable ? Math.max(-max, Math.min(max, this.steer)) : 0;
      wh.pivot.rotation.set(0, 0, a);
      wh.angle += (v.spin[i] || 0) * dt;
      wh.spin.quaternion.setFromAxisAngle(wh.axis, wh.angle);
      const k = wh.w.radial_stiffness;
      if (wh.w.strut) wh.lift = car && car.travel ? Math.max(-wh.w.radius, Math.min(wh.w.radius, car.travel[i] || 0)) : 0;
      else wh.lift = k > 0 ? Math.min(0.5 * wh.w.radius, Math.max(0, (v.N[i] || 0) / k)) : 0;
      wh.pivot.position.set(wh.w.pivot[0], wh.w.pivot[1], wh.w.pivot[2] + wh.lift);
      if (!this.figure) return;
      wh.pivot.updateMatrix(); wh.frame.updateMatrix(); wh.spin.updateMatrix();
      wh.matrix = m.clone().multiply(wh.pivot.matrix).multiply(wh.frame.matrix).multiply(wh.spin.matrix);
    });
    if (this.figure) this.updateFigure();
  }
  updateFigure() {
    const pts = this.layout.points, p = new THREE.Vector3();
    for (let k = 0; k < pts.length; ++k) {
      const [part, steerOf, x, y, z] = pts[k];
      p.set(x, y, z);
      if (part >= 0) p.applyMatrix4(this.wheels[part].matrix);
      else if (steerOf >= 0) {
        const wh = this.wheels[steerOf];
        p.sub(new THREE.Vector3(...wh.w.pivot)).applyAxisAngle(UP, wh.pivot.rotation.z).add(new THREE.Vector3(...wh.w.pivot));
      }
      this.pointPos.set([p.x, p.y, p.z], 3 * k);
    }
    const s = this.layout.springs;
    for (let k = 0; k < s.length; ++k) {
      this.springPos.set(this.pointPos.subarray(3 * s[k][0], 3 * s[k][0] + 3), 6 * k);
      this.springPos.set(this.pointPos.subarray(3 * s[k][1], 3 * s[k][1] + 3), 6 * k + 3);
    }
    this.points.geometry.attributes.position.needsUpdate = true;
    this.springs.geometry.attributes.position.needsUpdate = true;
  }
  // World position of wheel i's lowest point (where it marks the ground).
  contactPoint(i, out) {
    const wh = this.wheels[i];
    out.set(wh.w.offset[0], wh.w.offset[1], wh.w.offset[2] + wh.lift);
    this.root.localToWorld(out);
    out.z -= wh.w.radius;
    return out;
  }
  dispose(scene) {
    scene.remove(this.root);
    if (this.label) { scene.remove(this.label); this.label.material.map.dispose(); this.label.material.dispose(); }
  }
}
