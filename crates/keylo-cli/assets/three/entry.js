// The parts of three.js that `keylo report` uses, bundled into one classic script that
// defines `window.THREE` (a page opened from disk cannot import ES modules from files).
// Rebuild: bash build.sh (see README.md).
export {
  BufferGeometry,
  Color,
  Float32BufferAttribute,
  GridHelper,
  AxesHelper,
  Line,
  LineBasicMaterial,
  PerspectiveCamera,
  Points,
  PointsMaterial,
  Scene,
  Vector3,
  WebGLRenderer,
} from 'three';
export { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
