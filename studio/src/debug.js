// Visual debugging beside the preview: the derivation tree, the selected shape's leaves
// highlighted and its scope box drawn, clicking the model to select the shape under the
// pointer, an info panel (rule, scope, attributes), the generation slider, and the joints of a
// skinned model drawn and posed with sliders inside their limits.
//
// The server sends, with the GLB, the tree and which triangles of each glTF primitive are which
// leaf's (runs of [node, triangles]); nothing here depends on how the GLB groups its parts.
import {
  BufferAttribute, BufferGeometry, BoxGeometry, EdgesGeometry, Euler, Float32BufferAttribute, Group,
  LineBasicMaterial, LineSegments, MathUtils, Matrix4, Mesh, MeshBasicMaterial, Quaternion, Raycaster,
  SkinnedMesh, SphereGeometry, Vector2, Vector3,
} from "three";
import { TreeIndex, TreeView } from "./tree.js";

/** The highlight's colour: a magenta no example grammar uses, so tests can count it. */
const HIGHLIGHT = 0xff22cc;
const SCOPE_COLOR = 0x1060ff;
const JOINT_COLOR = 0xff7a00;

/** Attributes the highlight copies from the model's triangles (skinning ones follow poses). */
const COPIED = ["position", "normal", "skinIndex", "skinWeight"];

export class Debugger {
  /**
   * `preview` draws; `elements` are the panel's parts (tree, info, generation, generationValue,
   * joints); `hooks.rederive()` derives again (the generation changed), `hooks.jump(place)`
   * selects a rule in the editor.
   */
  constructor(preview, elements, hooks) {
    this.preview = preview;
    this.elements = elements;
    this.hooks = hooks;
    this.index = null;
    this.selected = -1;
    this.meshes = [];
    this.overlays = [];
    this.bones = [];
    /** Joint poses set with the sliders, by section name: kept when the model is derived again. */
    this.poses = new Map();
    this.view = new TreeView(elements.tree, (node) => this.select(node));
    this.scopeBox = new LineSegments(
      new EdgesGeometry(new BoxGeometry(1, 1, 1).translate(0.5, 0.5, 0.5)),
      new LineBasicMaterial({ color: SCOPE_COLOR, depthTest: false, transparent: true }),
    );
    this.scopeBox.renderOrder = 10;
    this.scopeBox.matrixAutoUpdate = false;
    this.scopeBox.visible = false;
    preview.scene.add(this.scopeBox);
    this.jointMarks = new Group();
    this.jointMarks.renderOrder = 11;
    preview.scene.add(this.jointMarks);
    this.jointMaterial = new MeshBasicMaterial({ color: JOINT_COLOR, depthTest: false, transparent: true });
    this.jointLineMaterial = new LineBasicMaterial({ color: JOINT_COLOR, depthTest: false, transparent: true });
    this.highlightMaterial = new MeshBasicMaterial({
      color: HIGHLIGHT, polygonOffset: true, polygonOffsetFactor: -2, polygonOffsetUnits: -2,
    });
    elements.generation.addEventListener("input", () => {
      this.showGeneration();
      this.hooks.rederive();
    });
    this.listenForPicks(preview.canvas);
  }

  /** Forgets the generation and the joint poses (another file). */
  reset() {
    this.elements.generation.max = "0";
    this.elements.generation.value = "0";
    this.poses.clear();
    this.index = null;
    this.selected = -1;
  }

  /** The generations to derive: `null` for all of them (the slider at its end). */
  generations() {
    const value = Number(this.elements.generation.value);
    return value >= Number(this.elements.generation.max) ? null : value;
  }

  showGeneration() {
    const { generation, generationValue } = this.elements;
    const all = this.generations() === null;
    generationValue.textContent = all ? `all (${generation.max})` : `${generation.value} of ${generation.max}`;
  }

  /**
   * Takes a new model and its tree before it is drawn: indexes the triangles by node, lists
   * the joints, keeps the selection when the same shape is still there and re-applies the
   * joint poses.
   */
  load(tree, gltf, generations) {
    this.clearHighlight();
    const open = this.index ? this.view.openNodes() : [];
    const previous = this.index && this.selected >= 0 ? this.index.name(this.selected) : null;
    this.index = tree ? new TreeIndex(tree) : null;
    if (generations === null && tree) {
      // A full derivation: the slider spans its generations.
      this.elements.generation.max = String(tree.generations);
      this.elements.generation.value = String(tree.generations);
    }
    this.showGeneration();
    this.meshes = [];
    if (!tree) {
      this.elements.tree.replaceChildren();
      this.scopeBox.visible = false;
      this.showInfo(-1);
      this.loadJoints(gltf);
      return;
    }
    const byPrimitive = new Map(tree.primitives.map((p) => [`${p.mesh}/${p.primitive}`, p.runs]));
    gltf.scene.traverse((object) => {
      const where = object.isMesh && gltf.parser.associations.get(object);
      const runs = where && byPrimitive.get(`${where.meshes}/${where.primitives}`);
      if (!runs) return;
      const triangles = object.geometry.index.count / 3;
      const nodes = new Int32Array(triangles).fill(-1);
      let at = 0;
      for (let i = 0; i < runs.length; i += 2) {
        nodes.fill(runs[i], at, Math.min(triangles, at + runs[i + 1]));
        at += runs[i + 1];
      }
      object.userData.nodes = nodes;
      this.meshes.push(object);
    });
    this.view.show(this.index, open);
    this.loadJoints(gltf);
    const keep = this.selected >= 0 && this.selected < this.index.count
      && this.index.name(this.selected) === previous;
    this.select(keep ? this.selected : -1, false);
  }

  /** Selects a node (or nothing, -1): tree row, highlight, scope box and info; draws the
   * preview again unless `render` is false. */
  select(node, render = true) {
    this.selected = node;
    this.clearHighlight();
    if (node < 0 || !this.index) {
      this.scopeBox.visible = false;
      this.showInfo(-1);
    } else {
      this.view.reveal(node);
      this.highlight(node);
      this.showScope(node);
      this.showInfo(node);
    }
    if (render) this.preview.render();
  }

  /** Draws the triangles of the node's leaves again in the highlight colour, over the model. */
  highlight(node) {
    const index = this.index;
    const inside = new Uint8Array(index.count);
    const stack = [node];
    while (stack.length) {
      const at = stack.pop();
      inside[at] = 1;
      for (const child of index.childrenOf(at)) stack.push(child);
    }
    for (const mesh of this.meshes) {
      const nodes = mesh.userData.nodes;
      const picked = [];
      for (let t = 0; t < nodes.length; t++) if (nodes[t] >= 0 && inside[nodes[t]]) picked.push(t);
      if (!picked.length) continue;
      const source = mesh.geometry;
      const geometry = new BufferGeometry();
      for (const name of COPIED) {
        const attribute = source.getAttribute(name);
        if (!attribute) continue;
        const size = attribute.itemSize;
        const data = new attribute.array.constructor(picked.length * 3 * size);
        let k = 0;
        for (const t of picked) {
          for (let c = 0; c < 3; c++) {
            const v = source.index.getX(t * 3 + c);
            for (let j = 0; j < size; j++) data[k++] = attribute.array[v * size + j];
          }
        }
        geometry.setAttribute(name, new BufferAttribute(data, size, attribute.normalized));
      }
      let overlay;
      if (mesh.isSkinnedMesh) {
        overlay = new SkinnedMesh(geometry, this.highlightMaterial);
        overlay.bind(mesh.skeleton, mesh.bindMatrix);
        overlay.frustumCulled = false;
        mesh.parent.add(overlay);
      } else {
        overlay = new Mesh(geometry, this.highlightMaterial);
        mesh.add(overlay);
      }
      overlay.renderOrder = 5;
      this.overlays.push(overlay);
    }
  }

  clearHighlight() {
    for (const overlay of this.overlays) {
      overlay.removeFromParent();
      overlay.geometry.dispose();
    }
    this.overlays = [];
  }

  /** The node's scope box at its birth (rest pose): a rectangle for a flat scope. */
  showScope(node) {
    const s = this.index.tree.scopes.slice(node * 15, node * 15 + 15);
    const [ox, oy, oz, xx, xy, xz, yx, yy, yz, zx, zy, zz, sx, sy, sz] = s;
    this.scopeBox.matrix.set(
      xx * sx, yx * sy, zx * sz, ox,
      xy * sx, yy * sy, zy * sz, oy,
      xz * sx, yz * sy, zz * sz, oz,
      0, 0, 0, 1,
    );
    this.scopeBox.matrixWorldNeedsUpdate = true;
    this.scopeBox.visible = true;
  }

  /** Fills the info panel: path, rule and where it is, scope, attributes. */
  showInfo(node) {
    const info = this.elements.info;
    if (node < 0 || !this.index) {
      info.replaceChildren(paragraph("Click a shape in the preview or the tree.", "hint"));
      return;
    }
    const tree = this.index.tree;
    const parts = [];
    const path = document.createElement("p");
    path.className = "path";
    this.index.path(node).reverse().forEach((at, i) => {
      if (i) path.append(" › ");
      const link = document.createElement("a");
      link.href = "#";
      link.textContent = this.index.name(at);
      link.addEventListener("click", (event) => {
        event.preventDefault();
        this.select(at);
      });
      path.append(link);
    });
    parts.push(path);
    const applied = tree.rule[node] >= 0 ? tree.rules[tree.rule[node]] : null;
    const rule = document.createElement("p");
    rule.className = "rule";
    const children = this.index.childrenOf(node).length;
    const what = children ? `${children} ${children === 1 ? "child" : "children"}` : "leaf";
    if (applied?.line) {
      const link = document.createElement("a");
      link.href = "#";
      link.textContent = `${applied.name} --> … (line ${applied.line})`;
      link.addEventListener("click", (event) => {
        event.preventDefault();
        this.hooks.jump(applied);
      });
      rule.append(`shape ${node} · ${what} · rule `, link);
    } else if (applied) {
      rule.append(`shape ${node} · ${what} · rule ${applied.name} (imported)`);
    } else {
      rule.append(`shape ${node} · ${what} · no rule applied`);
    }
    parts.push(rule);
    const s = tree.scopes.slice(node * 15, node * 15 + 15);
    const triple = (a) => `(${a.map((v) => +v.toFixed(4)).join(", ")})`;
    const rows = [
      ["origin", triple(s.slice(0, 3))],
      ["x axis", triple(s.slice(3, 6))],
      ["y axis", triple(s.slice(6, 9))],
      ["z axis", triple(s.slice(9, 12))],
      ["size", triple(s.slice(12, 15))],
      ...tree.attr_names.map((attr, i) => [attr, tree.attr_values[tree.attrs[node]][i]]),
    ];
    const table = document.createElement("table");
    for (const [key, value] of rows) {
      const row = table.insertRow();
      row.insertCell().textContent = key;
      row.insertCell().textContent = value;
    }
    parts.push(table);
    info.replaceChildren(...parts);
  }

  /** Clicking the model (a press without a drag) selects the shape under the pointer. */
  listenForPicks(canvas) {
    let down = null;
    canvas.addEventListener("pointerdown", (event) => {
      down = [event.clientX, event.clientY];
    });
    canvas.addEventListener("pointerup", (event) => {
      if (!down || Math.hypot(event.clientX - down[0], event.clientY - down[1]) > 4) return;
      const node = this.nodeAt(event.clientX, event.clientY);
      if (node !== null) this.select(node);
    });
  }

  /** The leaf's node under a point of the page (`-1`: no leaf's triangle; `null`: no model). */
  nodeAt(x, y) {
    if (!this.meshes.length) return null;
    const rect = this.preview.canvas.getBoundingClientRect();
    const pointer = new Vector2(((x - rect.left) / rect.width) * 2 - 1, -((y - rect.top) / rect.height) * 2 + 1);
    const raycaster = new Raycaster();
    raycaster.setFromCamera(pointer, this.preview.camera);
    const hit = raycaster.intersectObjects(this.meshes, false)[0];
    if (!hit) return -1;
    return hit.object.userData.nodes[hit.faceIndex] ?? -1;
  }

  /** The skinned meshes' joints (none without a glTF: a 2D drawing): marks at their places and a
   * slider per free axis. */
  loadJoints(gltf) {
    const bones = new Map();
    gltf?.scene.traverse((object) => {
      if (!object.isSkinnedMesh) return;
      object.frustumCulled = false;
      for (const bone of object.skeleton.bones) {
        const joint = bone.userData?.shapegram?.joint;
        if (joint && !bones.has(joint.section)) bones.set(joint.section, { bone, joint });
      }
    });
    this.bones = [...bones.values()];
    const list = this.elements.joints;
    list.replaceChildren();
    for (const { bone, joint } of this.bones) {
      const pose = this.poses.get(joint.section);
      if (pose) this.pose(bone, joint, pose);
      const sliders = [];
      for (const [kind, limits, unit, step] of [
        ["rotation", joint.rotation_limits_deg, "°", 0.5],
        ["translation", joint.translation_limits_m, " m", 0.01],
      ]) {
        limits.forEach(([min, max], axis) => {
          if (!(max > min)) return;
          const current = (pose || poseOf(joint))[kind][axis];
          sliders.push(this.slider(bone, joint, kind, axis, { min, max, unit, step, current }));
        });
      }
      if (!sliders.length) continue;
      const item = document.createElement("fieldset");
      const legend = document.createElement("legend");
      legend.textContent = joint.section;
      item.append(legend, ...sliders);
      list.append(item);
    }
    this.drawJoints();
  }

  slider(bone, joint, kind, axis, { min, max, unit, step, current }) {
    const label = document.createElement("label");
    const input = document.createElement("input");
    Object.assign(input, { type: "range", min, max, step, value: current });
    input.dataset.section = joint.section;
    input.dataset.kind = kind;
    input.dataset.axis = axis;
    const value = document.createElement("output");
    value.textContent = `${current}${unit}`;
    input.addEventListener("input", () => {
      const pose = this.poses.get(joint.section) || poseOf(joint);
      pose[kind][axis] = Number(input.value);
      this.poses.set(joint.section, pose);
      value.textContent = `${input.value}${unit}`;
      this.pose(bone, joint, pose);
      this.drawJoints();
      // Picking tests a skinned mesh's bounds first, which the pose moved.
      for (const mesh of this.meshes) {
        if (mesh.isSkinnedMesh) {
          mesh.computeBoundingBox();
          mesh.computeBoundingSphere();
        }
      }
      this.preview.render();
    });
    label.append(`${kind === "rotation" ? "rotate" : "move"} ${"xyz"[axis]} `, input, value);
    return label;
  }

  /**
   * Poses a bone as the engine does: its local transformation is rest · T(translation) ·
   * Rz · Ry · Rx (docs/kinematics.md), the rest part read from the joint's extras.
   */
  pose(bone, joint, pose) {
    const rest = new Matrix4().compose(
      new Vector3(...joint.rest_translation_m),
      new Quaternion(...joint.rest_rotation_xyzw),
      new Vector3(1, 1, 1),
    );
    const [rx, ry, rz] = pose.rotation.map((d) => MathUtils.degToRad(d));
    const moved = new Matrix4().compose(
      new Vector3(...pose.translation),
      new Quaternion().setFromEuler(new Euler(rx, ry, rz, "ZYX")),
      new Vector3(1, 1, 1),
    );
    rest.multiply(moved).decompose(bone.position, bone.quaternion, bone.scale);
  }

  /** A dot on every joint and a line to its parent joint, drawn over the model. */
  drawJoints() {
    for (const child of [...this.jointMarks.children]) {
      child.removeFromParent();
      child.geometry.dispose();
    }
    if (!this.bones.length) return;
    this.preview.scene.updateMatrixWorld(true);
    const material = this.jointMaterial;
    const radius = this.preview.modelSize() / 150;
    const places = new Map();
    const segments = [];
    for (const { bone } of this.bones) {
      const at = bone.getWorldPosition(new Vector3());
      places.set(bone, at);
      const dot = new Mesh(new SphereGeometry(radius, 8, 6), material);
      dot.position.copy(at);
      dot.renderOrder = 11;
      this.jointMarks.add(dot);
    }
    for (const { bone } of this.bones) {
      const parent = places.get(bone.parent);
      if (parent) segments.push(...parent.toArray(), ...places.get(bone).toArray());
    }
    if (segments.length) {
      const geometry = new BufferGeometry();
      geometry.setAttribute("position", new Float32BufferAttribute(segments, 3));
      const lines = new LineSegments(geometry, this.jointLineMaterial);
      lines.renderOrder = 11;
      this.jointMarks.add(lines);
    }
  }
}

/** A joint's current pose from its extras, as the sliders change it. */
function poseOf(joint) {
  return { rotation: [...joint.pose_rotation_deg], translation: [...joint.pose_translation_m] };
}

function paragraph(text, className) {
  const p = document.createElement("p");
  p.className = className;
  p.textContent = text;
  return p;
}
