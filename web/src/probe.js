// A check for tests (window.groundsim.debug.probeHorizon): draws the scene
// from a camera looking level at each of several headings, with the sky
// hidden and the clear colour a magenta that nothing else has, and counts
// the pixels of the rows just below the horizon line that kept the clear
// colour, i.e. where no ground was drawn. Restores the view after.
import * as THREE from 'three';

// opts: {x, y, z (camera), yaws: [rad], rows: how many rows below the horizon}
export function probeHorizon(world, { x, y, z, yaws = [0, Math.PI / 2, Math.PI, -Math.PI / 2], rows = 20, keep: show = false }) {
  const { renderer, camera, sky } = world;
  const gl = renderer.getContext();
  const keep = { pos: camera.position.clone(), q: camera.quaternion.clone(), sky: sky.visible,
    clear: renderer.getClearColor(new THREE.Color()), alpha: renderer.getClearAlpha() };
  sky.visible = false;
  renderer.setClearColor(0xff00ff, 1);
  // at 640 x 360 (a software renderer's frame is seconds at full size) and
  // without shadows: what is asked is where ground is, not how it is lit
  const size = renderer.getSize(new THREE.Vector2()), ratio = renderer.getPixelRatio(), aspect = camera.aspect;
  renderer.setPixelRatio(1);
  renderer.setSize(640, 360, false);
  camera.aspect = 640 / 360;
  camera.updateProjectionMatrix();
  const shadows = renderer.shadowMap.enabled;
  renderer.shadowMap.enabled = false;
  const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
  const horizon = Math.floor(h / 2);  // level camera: the horizon at infinity is the middle row
  const out = [];
  const px = new Uint8Array(w * rows * 4);
  for (const yaw of yaws) {
    camera.position.set(x, y, z);
    camera.lookAt(x + Math.cos(yaw), y + Math.sin(yaw), z);
    camera.updateMatrixWorld();
    renderer.render(world.scene, camera);
    // rows horizon-1 .. horizon-rows from the bottom of the buffer are the rows just below the horizon
    gl.readPixels(0, horizon - rows, w, rows, gl.RGBA, gl.UNSIGNED_BYTE, px);
    if (show) { out.push({ yaw, image: renderer.domElement.toDataURL('image/png') }); continue; }  // a picture of the probe
    let clear = 0;
    for (let i = 0; i < px.length; i += 4) if (px[i] > 240 && px[i + 1] < 15 && px[i + 2] > 240) clear++;
    out.push({ yaw, clear, pixels: w * rows, calls: renderer.info.render.calls, triangles: renderer.info.render.triangles });
  }
  const degPerRow = camera.fov / h;
  renderer.shadowMap.enabled = shadows;
  renderer.setPixelRatio(ratio);
  renderer.setSize(size.x, size.y, false);
  camera.aspect = aspect;
  camera.updateProjectionMatrix();
  camera.position.copy(keep.pos);
  camera.quaternion.copy(keep.q);
  sky.visible = keep.sky;
  renderer.setClearColor(keep.clear, keep.alpha);
  return { views: out, width: w, height: h, degPerRow };
}
