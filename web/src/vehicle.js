// One vehicle: a translucent body over its axle points, wheels that turn
// (spin integrated from the state's wheel_spin) and steer, and the report's
// figure 1 drawn over it: every mass point and spring of the model, placed
// from the layout the bridge built through the scenario layer. Suspension:
// each wheel is drawn raised by its deflection N / k (k: the radial
// stiffness of its coupling to the body), to scale; a road car's wheels
// ("strut" in the layout) by the suspension travel its car state reports.
import * as THREE from 'three';

const UP = new THREE.Vector3(0, 0, 1), Y = new THREE.Vector3(0, 1, 0);

// The report's car, for sessions whose scenario is unknown (a replay).
export function defaultLayout(name) {
  const wheel = (x, y, steer) => ({ offset: [x, y, 0], rotation: [1, 0, 0, 0], axis: [0, 1, 0], radius: 1,
    steerable: steer, max_steer: 0.6, pivot: [x, y, 0], radial_stiffness: 0 });
  return { name, lone_wheel: false, wheels: [wheel(1.5, 1, true), wheel(1.5, -1, true), wheel(-1.5, 1, false), wheel(-1.5, -1, false)],
    points: [], springs: [], body_min: [-1.5, -1.25, 0], body_max: [1.5, 1.25, 0] };
}

export class Vehicle {
  constructor(scene, layout, color) {
    this.layout = layout;
    this.root = new THREE.Group();
    scene.add(this.root);
    const lo = new THREE.Vector3(...layout.body_min), hi = new THREE.Vector3(...layout.body_max);
    const r = layout.wheels.length ? layout.wheels[0].radius : 0.5;
    this.size = Math.max(hi.x - lo.x, hi.y - lo.y, 2 * r, 0.5);
    if (!layout.lone_wheel) {
      const dims = new THREE.Vector3().subVectors(hi, lo).max(new THREE.Vector3(0.2, 0.2, 0.35 * r));
      const body = new THREE.Mesh(new THREE.BoxGeometry(dims.x, dims.y, dims.z),
        new THREE.MeshLambertMaterial({ color, transparent: true, opacity: 0.45 }));
      body.position.copy(lo).add(hi).multiplyScalar(0.5).add(new THREE.Vector3(0, 0, 0.1 * r));
      body.castShadow = true;
      this.root.add(body);
    }
    const tyre = new THREE.MeshLambertMaterial({ color: 0x222222 });
    const spokeMat = new THREE.MeshLambertMaterial({ color: 0xdddddd });
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
      const width = Math.max(0.15, 0.25 * w.radius);
      const tyreMesh = new THREE.Mesh(new THREE.CylinderGeometry(w.radius, w.radius, width, 28, 1, true), tyre);
      tyreMesh.castShadow = true;
      align.add(tyreMesh);
      for (let k = 0; k < 3; ++k) {  // spokes, so the turning shows
        const s = new THREE.Mesh(new THREE.BoxGeometry(2 * w.radius * 0.95, width * 0.5, 0.06 * w.radius), spokeMat);
        s.rotation.y = (k * Math.PI) / 3;
        align.add(s);
      }
      spin.add(align);
      frame.add(spin);
      pivot.add(frame);
      (layout.lone_wheel ? this.root : this.root).add(pivot);
      return { w, pivot, frame, spin, axis, angle: 0, lift: 0 };
    });
    // figure 1: points and springs, in body coordinates, rebuilt every frame
    const np = layout.points.length;
    this.pointPos = new Float32Array(np * 3);
    const pg = new THREE.BufferGeometry();
    pg.setAttribute('position', new THREE.BufferAttribute(this.pointPos, 3));
    this.points = new THREE.Points(pg, new THREE.PointsMaterial({ color: 0xffe066, size: Math.max(0.06, 0.06 * r) }));
    const sg = new THREE.BufferGeometry();
    this.springPos = new Float32Array(layout.springs.length * 6);
    sg.setAttribute('position', new THREE.BufferAttribute(this.springPos, 3));
    this.springs = new THREE.LineSegments(sg, new THREE.LineBasicMaterial({ color: 0x66ccff, transparent: true, opacity: 0.7 }));
    this.points.frustumCulled = this.springs.frustumCulled = false;
    this.root.add(this.points, this.springs);
    const front = layout.wheels.filter((w) => w.steerable), rear = layout.wheels.filter((w) => !w.steerable);
    this.wheelbase = front.length && rear.length ? Math.abs(front[0].offset[0] - rear[0].offset[0]) : 0;
    this.steer = 0;
  }

  // v: one interpolated vehicle of a state; dt: s of sim time since the last
  // frame; steer: rad commanded (own car), or null to estimate from the motion;
  // car: the newest road-car state of this vehicle (travel, steer_angle) or null
  update(v, dt, steer, car = null) {
    this.root.position.set(...v.p);
    this.root.quaternion.set(v.q[1], v.q[2], v.q[3], v.q[0]);
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
      wh.pivot.updateMatrix(); wh.frame.updateMatrix(); wh.spin.updateMatrix();
      wh.matrix = m.clone().multiply(wh.pivot.matrix).multiply(wh.frame.matrix).multiply(wh.spin.matrix);
    });
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
  dispose(scene) { scene.remove(this.root); }
}
