// The lot a grammar is derived on: the default 20 × 30 m lot, a polygon drawn on the ground in
// the preview (click its corners, then click the first corner again, press Enter or "Close" to
// close it), or a GeoJSON or OBJ file the user picks, whose text the server reads as
// `shapegram derive --lots` reads such a file.
import {
  BufferGeometry, Float32BufferAttribute, Group, Line, LineBasicMaterial, LineLoop, Plane, Points,
  PointsMaterial, Raycaster, Vector2, Vector3,
} from "three";

/** How far (in pixels) a click may be from the first corner to close the polygon there. */
const CLOSE_PX = 10;
/** How far the pointer may move between press and release for a click, not an orbit. */
const CLICK_PX = 4;

export class LotEditor {
  /** `preview` is the Preview drawn on; `onChange` is called when the lot changes. */
  constructor(root, preview, onChange) {
    this.preview = preview;
    this.onChange = onChange;
    this.mode = root.querySelector("#lot-mode");
    this.closeButton = root.querySelector("#lot-close");
    this.fileInput = root.querySelector("#lot-file");
    this.info = root.querySelector("#lot-info");
    /** The lot sent to the server; `null`: the default lot. */
    this.lot = null;
    this.points = [];
    this.drawing = false;
    this.overlay = new Group();
    this.overlay.name = "lot";
    preview.scene.add(this.overlay);
    this.mode.addEventListener("change", () => this.choose(this.mode.value));
    this.closeButton.addEventListener("click", () => this.close());
    this.fileInput.addEventListener("change", () => this.readFile());
    const canvas = preview.canvas;
    let down = null;
    canvas.addEventListener("pointerdown", (e) => { down = { x: e.clientX, y: e.clientY }; });
    canvas.addEventListener("pointerup", (e) => {
      if (!this.drawing || !down) return;
      if (Math.hypot(e.clientX - down.x, e.clientY - down.y) > CLICK_PX) return;
      this.click(e);
    });
    window.addEventListener("keydown", (e) => {
      if (this.drawing && e.key === "Enter") this.close();
      if (this.drawing && e.key === "Escape") this.choose("default");
    });
  }

  /** The lot for the derive request (absent: the default lot). */
  request() {
    return this.lot;
  }

  choose(mode) {
    this.mode.value = mode;
    this.drawing = mode === "draw";
    this.closeButton.hidden = !this.drawing;
    this.points = [];
    this.redraw();
    if (mode === "draw") {
      this.say("click the corners on the ground; click the first again (or Enter) to close");
    } else if (mode === "file") {
      this.fileInput.value = "";
      this.fileInput.click();
    } else if (this.lot !== null) {
      this.lot = null;
      this.say("the default lot, 20 × 30 m");
      this.onChange();
    }
  }

  /** The point on the ground (y = 0) under the pointer, or null. */
  ground(event) {
    const rect = this.preview.canvas.getBoundingClientRect();
    const ndc = new Vector2(
      ((event.clientX - rect.left) / rect.width) * 2 - 1,
      -((event.clientY - rect.top) / rect.height) * 2 + 1,
    );
    const ray = new Raycaster();
    ray.setFromCamera(ndc, this.preview.camera);
    return ray.ray.intersectPlane(new Plane(new Vector3(0, 1, 0), 0), new Vector3());
  }

  click(event) {
    const point = this.ground(event);
    if (!point) return;
    if (this.points.length >= 3) {
      const first = this.onScreen(this.points[0]);
      const rect = this.preview.canvas.getBoundingClientRect();
      if (Math.hypot(first.x - (event.clientX - rect.left), first.y - (event.clientY - rect.top)) < CLOSE_PX) {
        this.close();
        return;
      }
    }
    this.points.push([round(point.x), round(point.z)]);
    this.say(`${this.points.length} corners`);
    this.redraw();
  }

  /** A ground point's place on the canvas, in CSS pixels. */
  onScreen([x, z]) {
    const v = new Vector3(x, 0, z).project(this.preview.camera);
    const rect = this.preview.canvas.getBoundingClientRect();
    return { x: ((v.x + 1) / 2) * rect.width, y: ((1 - v.y) / 2) * rect.height };
  }

  close() {
    if (this.points.length < 3) {
      this.say(`a lot needs at least three corners (${this.points.length} so far)`);
      return;
    }
    this.drawing = false;
    this.closeButton.hidden = true;
    this.lot = { kind: "polygon", points: this.points };
    this.say(`a drawn lot of ${this.points.length} corners`);
    this.redraw();
    this.onChange();
  }

  async readFile() {
    const file = this.fileInput.files[0];
    if (!file) return;
    this.points = [];
    this.redraw();
    this.lot = { kind: "file", name: file.name, text: await file.text() };
    this.say(`lots from ${file.name}`);
    this.onChange();
  }

  say(text) {
    this.info.textContent = text;
  }

  /** The polygon drawn so far (or closed) as a line on the ground, with its corners. */
  redraw() {
    for (const child of [...this.overlay.children]) {
      this.overlay.remove(child);
      child.geometry.dispose();
      child.material.dispose();
    }
    if (this.points.length > 0) {
      // A little above the ground, so that the grid does not hide it.
      const positions = this.points.flatMap(([x, z]) => [x, 0.05, z]);
      const geometry = () => new BufferGeometry().setAttribute("position", new Float32BufferAttribute(positions, 3));
      const closed = this.lot?.kind === "polygon" && this.lot.points === this.points;
      const LineKind = closed ? LineLoop : Line;
      this.overlay.add(new LineKind(geometry(), new LineBasicMaterial({ color: 0xd0402a })));
      this.overlay.add(new Points(geometry(), new PointsMaterial({ color: 0xd0402a, size: 6, sizeAttenuation: false })));
    }
    this.preview.render();
  }
}

/** Corners to the centimetre: what is sent reads as typed. */
function round(v) {
  return Math.round(v * 100) / 100;
}
