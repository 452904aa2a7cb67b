// The preview of a 2D drawing (a flat L-system): the server's SVG shown as an image over the 3D
// canvas. An <img> from a blob: URL runs nothing in the SVG and fits the page's
// Content-Security-Policy.
export class Drawing {
  constructor(image) {
    this.image = image;
    this.url = null;
  }

  /** Shows `svg` (text); resolves once it is decoded. Returns its polylines and polygons. */
  async show(svg) {
    const parsed = new DOMParser().parseFromString(svg, "image/svg+xml");
    const url = URL.createObjectURL(new Blob([svg], { type: "image/svg+xml" }));
    this.image.src = url;
    this.image.hidden = false;
    await this.image.decode().catch(() => {});
    if (this.url) URL.revokeObjectURL(this.url);
    this.url = url;
    return {
      polylines: parsed.querySelectorAll("polyline").length,
      polygons: parsed.querySelectorAll("polygon").length,
      bytes: svg.length,
    };
  }

  /** Hides the drawing: the 3D canvas shows again. */
  hide() {
    this.image.hidden = true;
  }
}
