// The edit view (thesis 3.1, area 1): the sub-shapes of the edited rule, each in its own
// colour, with their edges, faces with a material in its colour or its texture; drag to
// rotate (orbit), wheel to zoom. It picks what the pointer is over (sub-shape and face, by the
// triangle ids the server sends; an anchor's arrow by its distance on screen) and draws the
// overlays the tools need: the selected face or shape, the sections of a pending cut, the
// 3-point cut's points and anchors. Geometry, texture coordinates and sections come from the
// server; this module only draws and picks.
import {
  WebGLRenderer, Scene, PerspectiveCamera, Color, HemisphereLight, DirectionalLight, Box3,
  Vector3, Vector2, BufferGeometry, Float32BufferAttribute, Mesh, MeshLambertMaterial,
  MeshBasicMaterial, LineSegments, LineBasicMaterial, Raycaster, Group, DoubleSide,
  SphereGeometry, ArrowHelper, TextureLoader, RepeatWrapping, SRGBColorSpace,
} from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";

export class EditView {
  constructor(canvas) {
    this.canvas = canvas;
    this.renderer = new WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.scene = new Scene();
    this.scene.background = new Color(0xdfe6ec);
    this.scene.add(new HemisphereLight(0xffffff, 0x8a8170, 2.2));
    const sun = new DirectionalLight(0xffffff, 1.6);
    sun.position.set(30, 60, 40);
    this.scene.add(sun);
    this.camera = new PerspectiveCamera(45, 1, 0.01, 5000);
    this.controls = new OrbitControls(this.camera, canvas);
    // Right-click completes cuts and places points: it must not pan.
    this.controls.mouseButtons = { LEFT: 0, MIDDLE: 1, RIGHT: -1 };
    this.controls.addEventListener("change", () => this.render());
    this.shapes = new Group();
    this.overlay = new Group();
    this.scene.add(this.shapes, this.overlay);
    this.parts = [];
    this.framedKey = null;
    this.raycaster = new Raycaster();
    this.textures = new Map();
    this.loader = new TextureLoader();
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.canvas;
    if (w === 0 || h === 0) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  /** Shows `parts` (the server's edit view), faces with a material in its colour or, when it
   * has one, its texture (`textureUrl(path)` is where the server serves it); frames the camera
   * when `key` (the edited rule or symbol) changes. */
  show(parts, key, materials = [], textureUrl = null) {
    clear(this.shapes);
    this.parts = parts;
    for (const part of parts) {
      if (part.hidden || part.kind === "epsilon") continue;
      const geometry = new BufferGeometry();
      geometry.setAttribute("position", new Float32BufferAttribute(part.positions, 3));
      geometry.computeVertexNormals();
      const colors = faceColors(part, materials);
      if (colors) geometry.setAttribute("color", new Float32BufferAttribute(colors, 3));
      const surface = { polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 };
      const plain = new MeshLambertMaterial({ color: colors ? 0xffffff : part.color, vertexColors: colors !== null, ...surface });
      const textured = textureUrl && part.uvs ? this.texturedFaces(part, geometry, materials, textureUrl, surface) : [];
      const mesh = new Mesh(geometry, textured.length ? [plain, ...textured] : plain);
      mesh.userData.part = part;
      this.shapes.add(mesh, edges(part, 0x2b3440));
    }
    // Removed volumes stay visible as outlines, so the user sees what the rule drops.
    for (const part of parts) {
      if (part.kind === "epsilon" && !part.hidden) this.shapes.add(edges(part, 0xb03030));
    }
    if (key !== this.framedKey) {
      this.framedKey = key;
      this.frame();
    }
    this.render();
  }

  /** Materials for the faces of `part` whose material has a texture, the geometry's groups
   * pointing at them (group material 0 is the plain one); none when no face is textured. */
  texturedFaces(part, geometry, materials, textureUrl, surface) {
    const chosen = part.face_materials || [];
    if (!chosen.some((m) => m != null && materials[m]?.texture)) return [];
    geometry.setAttribute("uv", new Float32BufferAttribute(part.uvs, 2));
    const made = new Map();
    const slot = (m) => {
      if (!made.has(m)) {
        const material = materials[m];
        made.set(m, {
          index: made.size + 1,
          material: new MeshLambertMaterial({ map: this.texture(textureUrl(material.texture)), color: material.color ?? 0xffffff, ...surface }),
        });
      }
      return made.get(m).index;
    };
    // Triangles come face by face, so each face is one run of them.
    const faces = part.triangle_faces;
    for (let start = 0; start < faces.length;) {
      let end = start;
      while (end < faces.length && faces[end] === faces[start]) end += 1;
      const m = chosen[faces[start]];
      geometry.addGroup(start * 3, (end - start) * 3, m != null && materials[m]?.texture ? slot(m) : 0);
      start = end;
    }
    return [...made.values()].map((x) => x.material);
  }

  /** The texture at `url`, loaded once and repeated (texture coordinates count tiles). */
  texture(url) {
    if (!this.textures.has(url)) {
      const texture = this.loader.load(url, () => this.render());
      texture.wrapS = RepeatWrapping;
      texture.wrapT = RepeatWrapping;
      texture.colorSpace = SRGBColorSpace;
      this.textures.set(url, texture);
    }
    return this.textures.get(url);
  }

  frame() {
    const box = new Box3();
    for (const part of this.parts) {
      for (const face of part.faces) for (const p of face) box.expandByPoint(new Vector3(...p));
    }
    if (box.isEmpty()) return this.render();
    const size = box.getSize(new Vector3()).length();
    const center = box.getCenter(new Vector3());
    this.controls.target.copy(center);
    this.camera.position.copy(center).add(new Vector3(0.8, 0.9, 1).normalize().multiplyScalar(size * 1.6));
    this.camera.near = size / 1000;
    this.camera.far = size * 100;
    this.camera.updateProjectionMatrix();
    this.controls.update();
  }

  /** The normalised device coordinates of a client point. */
  ndc(x, y) {
    const r = this.canvas.getBoundingClientRect();
    return new Vector2(((x - r.left) / r.width) * 2 - 1, -((y - r.top) / r.height) * 2 + 1);
  }

  /** The ray under a client point. */
  ray(x, y) {
    this.raycaster.setFromCamera(this.ndc(x, y), this.camera);
    return this.raycaster.ray;
  }

  /** The sub-shape and face under a client point, with the world point hit, or null. */
  pick(x, y) {
    this.raycaster.setFromCamera(this.ndc(x, y), this.camera);
    const meshes = this.shapes.children.filter((o) => o.isMesh);
    const hit = this.raycaster.intersectObjects(meshes, false)[0];
    if (!hit) return null;
    const part = hit.object.userData.part;
    return { part, node: part.node, face: part.triangle_faces[hit.faceIndex], point: hit.point };
  }

  /** Whether client point (x, y) is on the arrow of `anchor` (within a few pixels of it). */
  onAnchor(x, y, anchor) {
    const a = this.screenOf(anchor.from);
    const b = this.screenOf(anchor.to);
    const along = { x: b.x - a.x, y: b.y - a.y };
    const length2 = along.x * along.x + along.y * along.y;
    const t = length2 > 0 ? Math.min(Math.max(((x - a.x) * along.x + (y - a.y) * along.y) / length2, 0), 1) : 0;
    return Math.hypot(a.x + t * along.x - x, a.y + t * along.y - y) <= ANCHOR_GRIP;
  }

  /** Client coordinates of a world point (what the tests aim at). */
  screenOf(point) {
    const p = new Vector3(...point).project(this.camera);
    const r = this.canvas.getBoundingClientRect();
    return { x: r.left + ((p.x + 1) / 2) * r.width, y: r.top + ((1 - p.y) / 2) * r.height };
  }

  /** Draws the overlays: the selection, the sections of a pending cut, points, anchors and
   * the face an anchor is dragged over. */
  decorate({ selection, sections, points, anchors, preview, target }) {
    clear(this.overlay);
    // The anchor preview: the assigned symbol's rules applied to the sub-shape, see-through.
    for (const part of preview || []) {
      const geometry = new BufferGeometry();
      geometry.setAttribute("position", new Float32BufferAttribute(part.positions, 3));
      geometry.computeVertexNormals();
      const mesh = new Mesh(geometry, new MeshLambertMaterial({ color: part.color, transparent: true, opacity: 0.8, depthTest: false }));
      mesh.renderOrder = 1;
      this.overlay.add(mesh);
    }
    const part = selection && this.parts.find((p) => p.node === selection.node);
    if (part && selection.mode === "face") {
      this.overlay.add(polygon(part.faces[selection.face], 0xffd200, 0.85));
    } else if (part && selection.mode === "shape") {
      for (const face of part.faces) this.overlay.add(polygon(face, 0xffd200, 0.45));
    }
    for (const section of sections || []) this.overlay.add(polygon(section, 0xd02020, 0.4));
    const over = target && this.parts.find((p) => p.node === target.node);
    if (over) this.overlay.add(polygon(over.faces[target.face], 0x1010a0, 0.35));
    for (const p of points || []) {
      const dot = new Mesh(new SphereGeometry(this.dotSize(), 12, 8), new MeshBasicMaterial({ color: 0xd02020, depthTest: false }));
      dot.position.set(...p);
      dot.renderOrder = 2;
      this.overlay.add(dot);
    }
    for (const a of anchors || []) {
      const from = new Vector3(...a.from);
      const along = new Vector3(...a.to).sub(from);
      const arrow = new ArrowHelper(along.clone().normalize(), from, along.length(), 0x1010a0, along.length() * 0.3, along.length() * 0.15);
      for (const o of [arrow.line, arrow.cone]) {
        o.material.depthTest = false;
        o.renderOrder = 3;
      }
      this.overlay.add(arrow);
    }
    this.render();
  }

  dotSize() {
    const box = new Box3().setFromObject(this.shapes);
    return box.isEmpty() ? 0.02 : box.getSize(new Vector3()).length() / 80;
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }
}

/** How near (pixels) to an anchor's arrow a press grabs it. */
const ANCHOR_GRIP = 8;

function clear(group) {
  for (const o of [...group.children]) {
    group.remove(o);
    o.traverse((x) => {
      x.geometry?.dispose();
      for (const m of [x.material].flat()) m?.dispose();
    });
  }
}

/** The outline of every face of a part. */
function edges(part, color) {
  const points = [];
  for (const face of part.faces) {
    face.forEach((p, k) => points.push(...p, ...face[(k + 1) % face.length]));
  }
  const geometry = new BufferGeometry();
  geometry.setAttribute("position", new Float32BufferAttribute(points, 3));
  return new LineSegments(geometry, new LineBasicMaterial({ color }));
}

/** A convex polygon drawn see-through over the model. */
function polygon(corners, color, opacity) {
  const positions = [];
  for (let k = 1; k + 1 < corners.length; k++) positions.push(...corners[0], ...corners[k], ...corners[k + 1]);
  const geometry = new BufferGeometry();
  geometry.setAttribute("position", new Float32BufferAttribute(positions, 3));
  const mesh = new Mesh(geometry, new MeshBasicMaterial({ color, transparent: true, opacity, side: DoubleSide, depthTest: false }));
  mesh.renderOrder = 1;
  return mesh;
}

/** Per-corner colours (three numbers each) when some face of `part` has a material: those
 * faces in the material's colour, the others in the part's; `null` when none has one. */
function faceColors(part, materials) {
  const chosen = part.face_materials || [];
  if (!chosen.some((m) => m != null)) return null;
  const own = new Color(part.color);
  const colors = [];
  for (const face of part.triangle_faces) {
    const m = chosen[face];
    const c = m != null && materials[m] ? new Color(materials[m].surface) : own;
    for (let k = 0; k < 3; k += 1) colors.push(c.r, c.g, c.b);
  }
  return colors;
}
