// Dumps every attribute of a .drc with the npm draco3d decoder (Google's own,
// compiled to WebAssembly: independent of Debian's libdraco) as JSON:
// {"points", "triangles", "indices", "metadata": {name: value},
//  "attributes": [{"unique_id", "type" (Draco's attribute type), "data_type",
//  "components", "normalized", "metadata", "values" (as floats, point by
//  point)}]}.
// Metadata values are printed as draco3d's string reading of them (byte
// for byte comparable, whatever their type).
//   node attributes.mjs NODE_MODULES_DIR IN.drc
import { decodeMesh } from "./load.mjs";

const [modules, file] = process.argv.slice(2);
const { m, decoder, mesh, indices } = await decodeMesh(modules, file);
const querier = new m.MetadataQuerier();
function entries(metadata) {
  const out = {};
  if (!metadata || !metadata.ptr) return out;
  for (let i = 0; i < querier.NumEntries(metadata); ++i) {
    const name = querier.GetEntryName(metadata, i);
    out[name] = querier.GetStringEntry(metadata, name);
  }
  return out;
}
const attributes = [];
for (let i = 0; i < mesh.num_attributes(); ++i) {
  const a = decoder.GetAttribute(mesh, i);
  const values = new m.DracoFloat32Array();
  decoder.GetAttributeFloatForAllPoints(mesh, a, values);
  attributes.push({
    unique_id: a.unique_id(), type: a.attribute_type(), data_type: a.data_type(),
    components: a.num_components(), normalized: a.normalized(),
    metadata: entries(decoder.GetAttributeMetadata(mesh, i)),
    values: Array.from({ length: values.size() }, (_, k) => values.GetValue(k)),
  });
}
console.log(JSON.stringify({
  points: mesh.num_points(), triangles: mesh.num_faces(), indices,
  metadata: entries(decoder.GetMetadata(mesh)), attributes,
}));
