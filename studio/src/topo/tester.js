// The tester (thesis 3.1, beside the rule): a seed and a number of generations; "Test" asks the
// server to generate from the edited symbol and draws the model in its own small view; "Export
// GLB" has the server write that model beside the project.
import {
  WebGLRenderer, Scene, PerspectiveCamera, Color, HemisphereLight, DirectionalLight, Box3,
  Vector3, BufferGeometry, Float32BufferAttribute, Mesh, MeshLambertMaterial, Group,
} from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";

export class Tester {
  constructor(root, app) {
    this.app = app;
    this.seed = root.querySelector("#test-seed");
    this.generations = root.querySelector("#test-generations");
    this.result = root.querySelector("#test-result");
    this.canvas = root.querySelector("#test-canvas");
    root.querySelector("#test").addEventListener("click", () => this.run());
    root.querySelector("#export").addEventListener("click", () => this.export());
    this.renderer = new WebGLRenderer({ canvas: this.canvas, antialias: true, preserveDrawingBuffer: true });
    this.scene = new Scene();
    this.scene.background = new Color(0xeef1f4);
    this.scene.add(new HemisphereLight(0xffffff, 0x8a8170, 2.2));
    const sun = new DirectionalLight(0xffffff, 1.6);
    sun.position.set(30, 60, 40);
    this.scene.add(sun);
    this.model = new Group();
    this.scene.add(this.model);
    this.camera = new PerspectiveCamera(45, 1, 0.01, 5000);
    this.controls = new OrbitControls(this.camera, this.canvas);
    this.controls.addEventListener("change", () => this.render());
    this.last = null;
  }

  /** The tester's request for the edited symbol, or null (said in the status line). */
  job() {
    const symbol = this.app.editedSymbol();
    if (symbol == null) {
      this.app.status("choose a symbol or rule to test", true);
      return null;
    }
    return { symbol, seed: Number(this.seed.value) || 0, generations: Number(this.generations.value) || 0 };
  }

  async export() {
    const job = this.job();
    const answer = job && await this.app.request("export", job);
    if (answer) this.app.status(`exported ${answer.bytes} bytes to ${answer.path}`);
  }

  async run() {
    const job = this.job();
    if (!job) return;
    const answer = await this.app.request("test", job);
    if (!answer) return;
    this.last = answer;
    this.result.textContent = `generation ${answer.generation} · ${answer.terminals} terminals · `
      + `${answer.non_terminals} non-terminals · ${answer.triangles} triangles`;
    this.draw(answer.parts);
  }

  draw(parts) {
    for (const o of [...this.model.children]) {
      this.model.remove(o);
      o.geometry.dispose();
      o.material.dispose();
    }
    for (const part of parts) {
      const geometry = new BufferGeometry();
      geometry.setAttribute("position", new Float32BufferAttribute(part.positions, 3));
      geometry.computeVertexNormals();
      this.model.add(new Mesh(geometry, new MeshLambertMaterial({ color: part.color })));
    }
    const { clientWidth: w, clientHeight: h } = this.canvas;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    const box = new Box3().setFromObject(this.model);
    if (!box.isEmpty()) {
      const size = box.getSize(new Vector3()).length();
      const center = box.getCenter(new Vector3());
      this.controls.target.copy(center);
      this.camera.position.copy(center).add(new Vector3(0.8, 0.9, 1).normalize().multiplyScalar(size * 1.6));
      this.camera.near = size / 1000;
      this.camera.far = size * 100;
    }
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.render();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }
}
