// Dumps every attribute of a .drc with the npm draco3d decoder (Google's own,
// compiled to WebAssembly: independent of Debian's libdraco) as JSON:
// {"points", "triangles", "indices", "metadata": {name: value},
//  "attributes": [{"unique_id", "type" (Draco's attribute type), "data_type",
//  "components", "normalized", "metadata", "values" (as floats, point by
//  point)}]}.
// Metadata values are printed as draco3d's string reading of them (byte
// for byte comparable, whatever their type).
//   node attributes.mjs NODE_MODULES_DIR IN.drc
import { createRequire } from "node:module";
import { readFileSync } from "node:fs";
import path from "node:path";

const [modules, file] = process.argv.slice(2);
const draco3d = createRequire(path.join(path.resolve(modules), "noop.js"))("draco3d");
const m = await draco3d.createDecoderModule({});
const bytes = readFileSync(file);
const buffer = new m.DecoderBuffer();
buffer.Init(new Int8Array(bytes.buffer, bytes.byteOffset, bytes.byteLength), bytes.byteLength);
const decoder = new m.Decoder();
const mesh = new m.Mesh();
const status = decoder.DecodeBufferToMesh(buffer, mesh);
if (!status.ok()) {
  console.error(`${file}: ${status.error_msg()}`);
  process.exit(1);
}
const indices = [];
const face = new m.DracoInt32Array();
for (let f = 0; f < mesh.num_faces(); ++f) {
  decoder.GetFaceFromMesh(mesh, f, face);
  indices.push(face.GetValue(0), face.GetValue(1), face.GetValue(2));
}
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
