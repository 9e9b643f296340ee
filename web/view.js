// farfield's web viewer. Query parameters:
//   tileset=URL   a tileset.json (farfield export --format 3dtiles), or
//   glb=URL       a .glb (farfield export --format glb)
//   path=URL      a farfield camera path (farfield path ...), frame=N its pose (default 0);
//                 without one, the model seen whole from 25 degrees above the horizon
//   width, height the canvas in pixels (default: the window); hfov degrees (default 90)
//   error=PX      the tileset's screen-space error target in pixels (default 1, as
//                 clusters.error_px; 3d-tiles-renderer's own default is 16)
//   shot=1        no overlay (for screenshots)
// Shading is farfield's own (gpu/lighting.hpp): two directional lights opposite in heading,
// 14 degrees up, weight 0.55 each, ambient 0.35, colour = vertex colour x base colour
// x texture, unconverted (no sRGB), so a frame compares with farfield's pixel for pixel but
// for rasterisation, texture filtering and the tiles' level of detail.
// When everything asked is loaded, the overlay and document.title read "ready".
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { TilesRenderer } from '3d-tiles-renderer';

const params = new URLSearchParams(location.search);
const status = document.getElementById('status');
const say = (text) => { status.textContent = text; };
if (params.get('shot') === '1') document.body.classList.add('shot');

// farfield's lighting (gpu/lighting.hpp).
const kAmbient = 0.35, kLightWeight = 0.55, kElevation = 14, kHeading = 30;
const kSky = [0.70, 0.78, 0.85];
const radians = (d) => d * Math.PI / 180;
const lights = [0, 1].map((i) => {
  const h = radians(kHeading + 180 * i), e = radians(kElevation);
  return new THREE.Vector3(Math.cos(e) * Math.cos(h), Math.sin(e), Math.cos(e) * Math.sin(h));
});

THREE.ColorManagement.enabled = false;
const width = Number(params.get('width')) || innerWidth;
const height = Number(params.get('height')) || innerHeight;
const hfov = Number(params.get('hfov')) || 90;
const renderer = new THREE.WebGLRenderer({ antialias: false, reverseDepthBuffer: true });
renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
renderer.setPixelRatio(1);
renderer.setSize(width, height);
renderer.setClearColor(new THREE.Color(...kSky), 1);
document.body.appendChild(renderer.domElement);

const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(
  2 * Math.atan(Math.tan(radians(hfov) / 2) * height / width) * 180 / Math.PI, width / height,
  0.1, 1e6);

const vertexShader = `
in vec3 position; in vec3 normal; in vec4 color; in vec2 uv;
uniform mat4 modelMatrix, modelViewMatrix, projectionMatrix;
uniform vec3 light_dir[2]; uniform float ambient, weight;
out vec2 v_light; out vec4 v_color; out vec2 v_uv;
void main() {
  // At the vertices, on the front and on the back, as farfield's renderer (gpu/shaders.cpp).
  vec3 n = normalize(mat3(modelMatrix) * normal);
  vec2 d = vec2(dot(n, light_dir[0]), dot(n, light_dir[1]));
  v_light = ambient + weight * vec2(max(d.x, 0.0) + max(d.y, 0.0), max(-d.x, 0.0) + max(-d.y, 0.0));
  v_color = color;
  v_uv = uv;
  gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}`;
const fragmentShader = `
precision highp float;
uniform vec4 base; uniform sampler2D map; uniform bool textured; uniform float cutoff;
in vec2 v_light; in vec4 v_color; in vec2 v_uv;
out vec4 frag;
void main() {
  vec4 c = base * v_color;
  if (textured) c *= texture(map, v_uv);
  if (c.a < cutoff) discard;
  float light = gl_FrontFacing ? v_light.x : v_light.y;
  frag = vec4(min(c.rgb * light, vec3(1.0)), c.a);
}`;

// Every loaded mesh shaded as farfield shades it; glTF's material kept for its colour,
// texture, alpha mode and sides.
function farfieldShading(root) {
  root.traverse((o) => {
    if (!o.isMesh) return;
    const m = o.material;
    if (m.map) { m.map.colorSpace = THREE.NoColorSpace; m.map.needsUpdate = true; }
    if (!o.geometry.getAttribute('color')) {
      const n = o.geometry.getAttribute('position').count;
      o.geometry.setAttribute('color', new THREE.Float32BufferAttribute(new Float32Array(4 * n).fill(1), 4));
    }
    if (!o.geometry.getAttribute('uv'))
      o.geometry.setAttribute('uv', new THREE.Float32BufferAttribute(new Float32Array(2 * o.geometry.getAttribute('position').count), 2));
    o.material = new THREE.RawShaderMaterial({
      glslVersion: THREE.GLSL3, vertexShader, fragmentShader,
      uniforms: {
        base: { value: new THREE.Vector4(m.color.r, m.color.g, m.color.b, m.opacity) },
        map: { value: m.map ?? null }, textured: { value: !!m.map },
        cutoff: { value: m.alphaTest > 0 ? m.alphaTest : -1 },
        light_dir: { value: lights }, ambient: { value: kAmbient }, weight: { value: kLightWeight },
      },
      side: m.transparent ? THREE.DoubleSide : m.side,
      transparent: m.transparent, depthWrite: !m.transparent,
    });
  });
}

async function pose() {
  const url = params.get('path');
  if (!url) return null;
  const path = await (await fetch(url)).json();
  const frame = path.frames[Number(params.get('frame') ?? 0)];
  if (!frame) throw new Error(`${url}: no frame ${params.get('frame')}`);
  return frame;
}

function place(frame, bounds) {
  if (frame) {
    const [x, y, z] = frame.position;
    const yaw = radians(frame.yaw_deg), pitch = radians(frame.pitch_deg);
    camera.position.set(x, y, z);
    camera.lookAt(x + Math.cos(pitch) * Math.cos(yaw), y + Math.sin(pitch), z + Math.cos(pitch) * Math.sin(yaw));
  } else {
    const centre = bounds.getCenter(new THREE.Vector3());
    const r = bounds.getSize(new THREE.Vector3()).length();
    camera.position.copy(centre).add(new THREE.Vector3(r * Math.cos(radians(25)), r * Math.sin(radians(25)), 0));
    camera.lookAt(centre);
  }
  camera.updateMatrixWorld();
}

async function main() {
  const frame = await pose();
  const tilesetUrl = params.get('tileset'), glbUrl = params.get('glb');
  if (glbUrl) {
    const gltf = await new GLTFLoader().loadAsync(glbUrl);
    farfieldShading(gltf.scene);
    scene.add(gltf.scene);
    place(frame, new THREE.Box3().setFromObject(gltf.scene));
    renderer.render(scene, camera);
    say('ready'); document.title = 'ready';
    return;
  }
  if (!tilesetUrl) { say('give ?tileset=URL or ?glb=URL'); return; }
  const tiles = new TilesRenderer(tilesetUrl);
  tiles.errorTarget = Number(params.get('error') ?? 1);
  if (tiles.lruCache) { tiles.lruCache.maxSize = 1e6; tiles.lruCache.minSize = 0; tiles.lruCache.maxBytesSize = 4e9; }
  tiles.group.rotation.x = -Math.PI / 2;  // 3D Tiles' +Z up back to glTF's (farfield's) +Y up
  scene.add(tiles.group);
  tiles.addEventListener('load-model', ({ scene: model }) => farfieldShading(model));
  let placed = !!frame, loadedOnce = false;
  if (frame) place(frame);
  tiles.addEventListener('load-tileset', () => {
    if (placed) return;
    const box = new THREE.Box3(), matrix = new THREE.Matrix4();
    if (tiles.getBoundingBox(box)) { place(null, box.applyMatrix4(matrix.makeRotationX(-Math.PI / 2))); placed = true; }
  });
  tiles.addEventListener('tiles-load-end', () => { loadedOnce = true; });
  tiles.setCamera(camera);
  tiles.setResolutionFromRenderer(camera, renderer);
  let quiet = 0;
  renderer.setAnimationLoop(() => {
    tiles.update();
    renderer.render(scene, camera);
    const s = tiles.stats;
    const busy = s.downloading + s.parsing + (s.queued ?? 0);
    quiet = loadedOnce && busy === 0 ? quiet + 1 : 0;
    if (quiet >= 10 && document.title !== 'ready') {
      say('ready'); document.title = 'ready';
    } else if (quiet < 10) {
      say(`loading: ${s.downloading} downloading, ${s.parsing} parsing, ${s.failed} failed, ` +
          `${tiles.visibleTiles?.size ?? '?'} visible, ${tiles.activeTiles?.size ?? '?'} active, ` +
          `${s.inCache ?? '?'} cached`);
    }
  });
}
main().catch((e) => { say(`error: ${e.message}`); document.title = `error: ${e.message}`; console.error(e); });
