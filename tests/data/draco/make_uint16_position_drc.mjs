// Writes uint16_position.drc: a tetrahedron whose POSITION is 3 uint16
// (not normalized), as quantizing tools (gltfpack, then gltf-transform's
// Draco) store positions, and no NORMAL, encoded by the npm draco3d
// encoder. A standalone stream's integer coordinates are in its own units.
//   node make_uint16_position_drc.mjs NODE_MODULES OUT.drc
import { createRequire } from "node:module";
import { writeFileSync } from "node:fs";
import path from "node:path";

const [modules, out] = process.argv.slice(2);
const draco3d = createRequire(path.join(path.resolve(modules), "noop.js"))("draco3d");
const m = await draco3d.createEncoderModule({});
const positions = [0, 0, 0, 1000, 0, 0, 0, 1000, 0, 0, 0, 1000];
const indices = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3];
const mesh = new m.Mesh();
const builder = new m.MeshBuilder();
builder.AddFacesToMesh(mesh, indices.length / 3, new Uint32Array(indices));
builder.AddUInt16Attribute(mesh, m.POSITION, 4, 3, new Uint16Array(positions));
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
