// The three.js side that every view shares: renderer, scene, camera, a sky
// dome with the sun, fog to the horizon (the sky's horizon colour, so far
// ground fades into the sky without an edge), the sun's shadow following
// the car. The sky is drawn only while a session or a replay is shown (the
// lobby stays one plain colour).
import * as THREE from 'three';

export const FOG = new THREE.Color(0xc3d3e2);     // horizon haze
const ZENITH = new THREE.Color(0x3f78c0);
const CLEAR = 0x1b1f24;
export const SUN_DIR = new THREE.Vector3(-0.45, -0.3, 0.84).normalize();  // towards the sun

function skyDome() {
  const material = new THREE.ShaderMaterial({
    uniforms: { horizon: { value: FOG }, zenith: { value: ZENITH }, sun: { value: SUN_DIR } },
    vertexShader: `varying vec3 vDir;
      void main() { vDir = normalize(position); gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0); }`,
    fragmentShader: `uniform vec3 horizon, zenith, sun; varying vec3 vDir;
      void main() {
        vec3 d = normalize(vDir);
        float up = max(d.z, 0.0);
        vec3 c = mix(horizon, zenith, pow(up, 0.45));
        float s = max(dot(d, sun), 0.0);
        c += vec3(1.0, 0.9, 0.7) * (pow(s, 900.0) * 2.0 + pow(s, 12.0) * 0.18);
        gl_FragColor = vec4(c, 1.0);
      }`,
    side: THREE.BackSide, depthWrite: false, fog: false,
  });
  const m = new THREE.Mesh(new THREE.SphereGeometry(1, 32, 16), material);
  m.renderOrder = -1;
  m.frustumCulled = false;
  return m;
}

export class World {
  constructor(container) {
    const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(Math.min(2, window.devicePixelRatio || 1));
    renderer.setSize(window.innerWidth, window.innerHeight);
    renderer.setClearColor(CLEAR);
    renderer.shadowMap.enabled = true;
    renderer.shadowMap.type = THREE.PCFShadowMap;
    container.appendChild(renderer.domElement);
    const scene = new THREE.Scene();
    scene.fog = new THREE.FogExp2(FOG, 0.00032);  // of the ground, 90 % seen at 1 km, 19 % at 4 km, none at 8 km
    scene.add(new THREE.HemisphereLight(0xdfefff, 0x5a5040, 1.3));
    const sun = new THREE.DirectionalLight(0xfff2dd, 2.4);
    sun.castShadow = true;
    sun.shadow.mapSize.set(1024, 1024);
    sun.shadow.bias = -0.0005;
    sun.shadow.normalBias = 0.03;
    Object.assign(sun.shadow.camera, { left: -22, right: 22, top: 22, bottom: -22, near: 1, far: 120 });
    scene.add(sun, sun.target);
    const camera = new THREE.PerspectiveCamera(55, window.innerWidth / window.innerHeight, 0.25, 40000);
    camera.up.set(0, 0, 1);
    camera.position.set(-8, -6, 5);
    const sky = skyDome();
    sky.scale.setScalar(30000);
    sky.visible = false;
    scene.add(sky);
    Object.assign(this, { renderer, scene, camera, sun, sky });
    window.addEventListener('resize', () => {
      camera.aspect = window.innerWidth / window.innerHeight;
      camera.updateProjectionMatrix();
      renderer.setSize(window.innerWidth, window.innerHeight);
    });
  }
  // the sun's shadow box around p (the followed car), the dome around the camera
  follow(p) {
    this.sun.position.set(p[0] + 60 * SUN_DIR.x, p[1] + 60 * SUN_DIR.y, p[2] + 60 * SUN_DIR.z);
    this.sun.target.position.set(p[0], p[1], p[2]);
  }
  render() {
    this.sky.position.copy(this.camera.position);
    this.renderer.render(this.scene, this.camera);
  }
}
