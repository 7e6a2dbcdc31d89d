// Decodes a .drc with the npm draco3d decoder (Google's own, compiled to
// WebAssembly: independent of Debian's libdraco) and prints it as JSON:
// {"points", "triangles", "positions", "indices", "normals" (null if none)}.
//   node decode.mjs NODE_MODULES_DIR IN.drc        the JSON on stdout
//   node decode.mjs NODE_MODULES_DIR --to IN.drc OUT.json [IN.drc OUT.json]...
//                                                  each IN's JSON in its OUT (one
//                                                  start for many files)
import { writeFileSync } from "node:fs";
import { decodeMesh } from "./load.mjs";

async function decodeJson(modules, file) {
  const { m, decoder, mesh, indices } = await decodeMesh(modules, file);
  function floats(type) {
    const id = decoder.GetAttributeId(mesh, type);
    if (id < 0) return null;
    const values = new m.DracoFloat32Array();
    decoder.GetAttributeFloatForAllPoints(mesh, decoder.GetAttribute(mesh, id), values);
    const out = Array.from({ length: values.size() }, (_, i) => values.GetValue(i));
    m.destroy(values);
    return out;
  }
  const json = JSON.stringify({
    points: mesh.num_points(), triangles: mesh.num_faces(),
    positions: floats(m.POSITION), indices, normals: floats(m.NORMAL),
  });
  m.destroy(mesh);
  m.destroy(decoder);
  return json;
}

const [modules, ...files] = process.argv.slice(2);
if (files[0] === "--to") {
  if (files.length < 3 || files.length % 2 === 0) {
    console.error("usage: node decode.mjs NODE_MODULES_DIR --to IN.drc OUT.json [IN.drc OUT.json]...");
    process.exit(2);
  }
  for (let i = 1; i + 1 < files.length; i += 2) writeFileSync(files[i + 1], (await decodeJson(modules, files[i])) + "\n");
} else {
  console.log(await decodeJson(modules, files[0]));
}
