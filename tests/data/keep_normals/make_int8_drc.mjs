// Writes loose_int8.drc: vertices 0-6 of loose.off with their normals as
// normalized int8 (value * 127, rounded), as glTF's KHR_mesh_quantization and
// tools like gltfpack store normals, encoded by the npm draco3d encoder
// (sequential, speed 10: Draco 1.5.5's normal prediction at lower speeds keeps
// only float normals intact).
//   node make_int8_drc.mjs NODE_MODULES OUT.drc
import { createRequire } from "node:module";
import { writeFileSync } from "node:fs";
import path from "node:path";

const [modules, out] = process.argv.slice(2);
const draco3d = createRequire(path.join(path.resolve(modules), "noop.js"))("draco3d");
const m = await draco3d.createEncoderModule({});
const positions = [0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0.5, 2, 0, 0, 3, 0, 0, 4, 0, 0];
const normals = [0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0.6, 0, 0.8, 0, -0.6, 0.8, -0.28, 0.96, 0];
const indices = [0, 1, 2, 1, 3, 2, 4, 5, 6];
const mesh = new m.Mesh();
const builder = new m.MeshBuilder();
builder.AddFacesToMesh(mesh, indices.length / 3, new Uint32Array(indices));
builder.AddFloatAttributeToMesh(mesh, m.POSITION, 7, 3, new Float32Array(positions));
const id = builder.AddInt8Attribute(mesh, m.NORMAL, 7, 3, new Int8Array(normals.map((v) => Math.round(v * 127))));
builder.SetNormalizedFlagForAttribute(mesh, id, true);
const encoder = new m.Encoder();
encoder.SetSpeedOptions(10, 10);
encoder.SetEncodingMethod(m.MESH_SEQUENTIAL_ENCODING);
const data = new m.DracoInt8Array();
const n = encoder.EncodeMeshToDracoBuffer(mesh, data);
if (n <= 0) {
  console.error("encoding failed");
  process.exit(1);
}
const bytes = new Uint8Array(n);
for (let i = 0; i < n; ++i) bytes[i] = data.GetValue(i) & 0xff;
writeFileSync(out, bytes);
