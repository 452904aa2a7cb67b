// The 3D preview: the derived GLB loaded with three.js's GLTFLoader, orbit controls, and a
// render only when something changed (no free-running loop: an idle page costs nothing, and
// tests can tell when a model is drawn).
import {
  WebGLRenderer, Scene, PerspectiveCamera, Color, HemisphereLight, DirectionalLight, GridHelper,
  Box3, Vector3, RepeatWrapping,
} from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";

export class Preview {
  constructor(canvas) {
    this.canvas = canvas;
    // Kept so that the page (and its tests) can read what is shown.
    this.renderer = new WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.scene = new Scene();
    this.scene.background = new Color(0xdfe6ec);
    this.scene.add(new HemisphereLight(0xffffff, 0x8a8170, 2.2));
    const sun = new DirectionalLight(0xffffff, 1.8);
    sun.position.set(30, 60, 40);
    this.scene.add(sun);
    this.grid = new GridHelper(100, 50, 0x9aa4ad, 0xc4ccd3);
    this.scene.add(this.grid);
    this.camera = new PerspectiveCamera(45, 1, 0.1, 5000);
    this.camera.position.set(40, 30, 40);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener("change", () => this.render());
    this.loader = new GLTFLoader();
    this.model = null;
    this.framed = false;
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  /** Forgets the camera's framing: the next model is framed anew (another file). */
  reset() {
    this.framed = false;
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.canvas;
    if (w === 0 || h === 0) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  /** The length of the model's bounding box's diagonal (1 without a model). */
  modelSize() {
    const box = this.model && new Box3().setFromObject(this.model);
    return box && !box.isEmpty() ? box.getSize(new Vector3()).length() : 1;
  }

  /** Replaces the model with the GLB in `buffer`; frames the camera on the first one.
   * `loaded(gltf)` may add to the scene before it is drawn (the glTF's parser knows which glTF
   * primitive each mesh is). */
  async show(buffer, loaded) {
    const gltf = await this.loader.parseAsync(buffer, "");
    if (this.model) {
      this.scene.remove(this.model);
      this.model.traverse((o) => {
        o.geometry?.dispose();
        for (const m of [o.material].flat()) {
          // A material's textures (the GLB's embedded images) are freed with it.
          for (const value of Object.values(m ?? {})) if (value?.isTexture) value.dispose();
          m?.dispose();
        }
      });
    }
    this.model = gltf.scene;
    this.scene.add(this.model);
    if (!this.framed) {
      this.frame();
      this.framed = true;
    }
    loaded?.(gltf);
    this.render();
  }

  /** The shown model's materials that draw an image (a textured CGA part, a topological
   * grammar's material): name, image size and wrapping, once per material. */
  textures() {
    const found = new Map();
    this.model?.traverse((o) => {
      for (const m of [o.material ?? []].flat()) {
        const image = m.map?.image;
        if (image && !found.has(m.name)) {
          found.set(m.name, { material: m.name, width: image.width, height: image.height, repeats: m.map.wrapS === RepeatWrapping && m.map.wrapT === RepeatWrapping });
        }
      }
    });
    return [...found.values()];
  }

  /** Points the camera at the model from above a front corner, at a distance that shows it. */
  frame() {
    const box = new Box3().setFromObject(this.model);
    if (box.isEmpty()) return;
    const size = box.getSize(new Vector3()).length();
    const center = box.getCenter(new Vector3());
    this.controls.target.copy(center);
    this.camera.position.copy(center).add(new Vector3(0.8, 0.6, 1).normalize().multiplyScalar(size * 1.3));
    this.camera.near = size / 1000;
    this.camera.far = size * 100;
    this.camera.updateProjectionMatrix();
    this.controls.update();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }
}
