// Decodes a .drc with the npm draco3d decoder (Google's own, compiled to
// WebAssembly: independent of Debian's libdraco) and prints it as JSON:
// {"points", "triangles", "positions", "indices", "normals" (null if none)}.
//   node decode.mjs NODE_MODULES_DIR IN.drc
import { decodeMesh } from "./load.mjs";

const [modules, file] = process.argv.slice(2);
const { m, decoder, mesh, indices } = await decodeMesh(modules, file);
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
