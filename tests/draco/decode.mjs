// Decodes a .drc with the npm draco3d decoder (Google's own, compiled to
// WebAssembly: independent of Debian's libdraco) and prints it as JSON:
// {"points", "triangles", "positions", "indices", "normals" (null if none)}.
//   node decode.mjs NODE_MODULES_DIR IN.drc
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
if (decoder.GetEncodedGeometryType(buffer) !== m.TRIANGULAR_MESH) {
  console.error(`${file}: not a Draco mesh`);
  process.exit(1);
}
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
function floats(type) {
  const id = decoder.GetAttributeId(mesh, type);
  if (id < 0) return null;
  const values = new m.DracoFloat32Array();
  decoder.GetAttributeFloatForAllPoints(mesh, decoder.GetAttribute(mesh, id), values);
  return Array.from({ length: values.size() }, (_, i) => values.GetValue(i));
}
console.log(JSON.stringify({
  points: mesh.num_points(), triangles: mesh.num_faces(),
  positions: floats(m.POSITION), indices, normals: floats(m.NORMAL),
}));
