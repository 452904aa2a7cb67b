// The tileset as 3d-tiles-tools reads it: its traverser walks every tile of tileset.json, its
// content-type registry must recognise every content as GLB, and the geometric error must
// fall from each tile to its children, down to 0 at the leaves.
import { readFileSync } from "node:fs";
import { join } from "node:path";
import assert from "node:assert/strict";
import { ContentDataTypeRegistry, ResourceResolvers, TilesetTraverser } from "3d-tiles-tools";

/** Checks the tileset in `dir`; resolves with the URIs of its contents by level. */
export async function checkTileset(dir) {
  const tileset = JSON.parse(readFileSync(join(dir, "tileset.json"), "utf8"));
  assert.equal(tileset.asset.version, "1.1");
  const resolver = ResourceResolvers.createFileResourceResolver(dir);
  const traverser = new TilesetTraverser(dir, resolver, { depthFirst: true });
  const byLevel = [];
  const errors = new Map();
  await traverser.traverse(tileset, async (traversed) => {
    const tile = traversed.asRawTile();
    const level = traversed.level;
    const parent = traversed.getParent();
    if (parent) {
      const parentError = errors.get(parent.asRawTile());
      assert.ok(tile.geometricError < parentError, `error ${tile.geometricError} under ${parentError}`);
    }
    errors.set(tile, tile.geometricError);
    assert.equal(tile.boundingVolume.box.length, 12);
    for (const content of traversed.getRawContents()) {
      const data = await resolver.resolveData(content.uri);
      assert.ok(data, `no data for ${content.uri}`);
      const type = await ContentDataTypeRegistry.findType(content.uri, data);
      assert.equal(type, "CONTENT_TYPE_GLB", content.uri);
      (byLevel[level] ??= []).push(content.uri);
    }
    if ((await traversed.getChildren()).length === 0) assert.equal(tile.geometricError, 0);
    return true;
  });
  return byLevel;
}
