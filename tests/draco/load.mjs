// Shared by decode.mjs and attributes.mjs: a .drc decoded as a mesh with the
// npm draco3d decoder (Google's own, compiled to WebAssembly: independent of
// Debian's libdraco). Exits 1 with a message when it is not one.
import { createRequire } from "node:module";
import { readFileSync } from "node:fs";
import path from "node:path";

// One decoder module for every file of a process: starting it is most of the
// time a small file takes.
let decoderModule = null;

// {m: the decoder module, decoder, mesh, indices: 3 per triangle}; the caller
// may m.destroy() decoder and mesh when done.
export async function decodeMesh(modules, file) {
  if (!decoderModule) {
    const draco3d = createRequire(path.join(path.resolve(modules), "noop.js"))("draco3d");
    decoderModule = await draco3d.createDecoderModule({});
  }
  const m = decoderModule;
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
  m.destroy(buffer);
  const indices = [];
  const face = new m.DracoInt32Array();
  for (let f = 0; f < mesh.num_faces(); ++f) {
    decoder.GetFaceFromMesh(mesh, f, face);
    indices.push(face.GetValue(0), face.GetValue(1), face.GetValue(2));
  }
  m.destroy(face);
  return { m, decoder, mesh, indices };
}
