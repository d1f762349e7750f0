// Cameras: "chase" behind the followed car, "orbit" around it (mouse drag
// turns, wheel zooms, the target moves with the car), and "free" (orbit,
// pan and zoom anywhere; the car is not followed), offered while replaying.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

export class CameraRig {
  constructor(camera, dom) {
    this.camera = camera;
    this.orbit = new OrbitControls(camera, dom);
    this.orbit.enabled = false;
    this.orbit.maxPolarAngle = Math.PI * 0.495;
    this.mode = 'chase';
    this.target = new THREE.Vector3();
    this.onChange = null;
  }
  // the modes a view offers, in the order C cycles through them
  set(mode) {
    this.mode = mode;
    this.orbit.enabled = mode !== 'chase';
    this.orbit.screenSpacePanning = false;
    if (this.onChange) this.onChange(mode);
  }
  cycle(modes) {
    this.set(modes[(modes.indexOf(this.mode) + 1) % modes.length]);
  }
  // v: the followed vehicle's state (p, q); size: its length; dt: s since the last frame
  place(v, size, dt) {
    if (this.mode === 'free') { this.orbit.update(); return; }
    if (!v) return;
    this.target.set(...v.p);
    if (this.mode === 'orbit') {
      const d = this.target.clone().sub(this.orbit.target);
      this.orbit.target.add(d);
      this.camera.position.add(d);
      this.orbit.update();
      return;
    }
    const q = new THREE.Quaternion(v.q[1], v.q[2], v.q[3], v.q[0]);
    const fwd = new THREE.Vector3(1, 0, 0).applyQuaternion(q);
    fwd.z = 0;
    if (fwd.lengthSq() < 1e-6) fwd.set(1, 0, 0);
    fwd.normalize();
    const want = this.target.clone().addScaledVector(fwd, -2.2 * size).add(new THREE.Vector3(0, 0, 0.75 * size));
    this.camera.position.lerp(want, Math.min(1, 4 * dt));
    this.camera.lookAt(this.target.clone().add(new THREE.Vector3(0, 0, 0.25 * size)));
    this.orbit.target.copy(this.target);
  }
}
