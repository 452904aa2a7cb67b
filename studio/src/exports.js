// Downloads of the model shown as GLB, OBJ (with its MTL) or STL: the same text, attributes,
// seed and lot as the preview, written by the server's exporters (POST /api/export).

/** Saves `bytes` as the file `name`. */
export function save(bytes, name, type) {
  const url = URL.createObjectURL(new Blob([bytes], { type }));
  const link = document.createElement("a");
  link.href = url;
  link.download = name;
  document.body.append(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

const TYPES = { glb: "model/gltf-binary", obj: "model/obj", mtl: "text/plain", stl: "model/stl" };

/** Asks the server for the model of `request` (a derive request) in `format` and saves its
 * files; resolves with the files' names, or throws with the server's message. */
export async function download(request, format) {
  const response = await fetch("/api/export", {
    method: "POST",
    headers: { "content-type": "application/json" },
    body: JSON.stringify({ ...request, format }),
  });
  const json = await response.json();
  if (response.status !== 200) throw new Error(json.error);
  for (const file of json.files) {
    const bytes = Uint8Array.from(atob(file.data), (c) => c.charCodeAt(0));
    save(bytes, file.name, TYPES[file.name.split(".").pop()] || "application/octet-stream");
  }
  return json.files.map((f) => f.name);
}
