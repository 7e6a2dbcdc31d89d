// Compares a glTF file vn wrote with its input, decoding EXT/KHR_meshopt_compression with the
// npm meshoptimizer decoder (independent of vn's C++ meshoptimizer):
//   node meshopt.mjs NODE_MODULES_DIR INPUT OUTPUT [--plain | --kept] [--normals REFERENCE]
// - every accessor other than NORMAL (found by what uses it: primitive attributes, indices and
//   morph targets, skins, animation samplers) decodes to the input's values exactly;
// - every NORMAL of a primitive is a unit vector (within its type's quantization) and, with
//   --normals, within quantization of REFERENCE's (e.g. vn's --meshopt off output);
// - a bufferView of OUTPUT whose fallback buffer has data holds what its compressed data decode to;
// - OUTPUT's buffers with data hold nothing but what bufferViews and their meshopt extensions refer
//   to (and padding to a multiple of 4 before each);
// OCTAHEDRAL and QUATERNION filters are decoded to one unit in the last place (the specification's
// precision: decoders differ that much), so their values may differ by 1.
// - --plain: no meshopt extension is left (bufferViews, buffers, extensionsUsed/Required);
// - --kept: every accessor the input compressed is compressed in the output with the same mode, and
//   with the same filter and in the same bytes unless its bufferView holds a NORMAL (vn may append a
//   NORMAL plain).
// Prints what it checked; exit status 1 on a failure.
import { readFile } from 'node:fs/promises';
import { createRequire } from 'node:module';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const args = process.argv.slice(2);
const flag = (name) => (args.includes(name) ? (args.splice(args.indexOf(name), 1), true) : false);
const option = (name) => (args.includes(name) ? args.splice(args.indexOf(name), 2)[1] : null);
const plain = flag('--plain'), kept = flag('--kept'), reference = option('--normals');
const [modules, input, output] = args;
const decoderPath = createRequire(path.join(path.resolve(modules), 'x.js')).resolve('meshoptimizer/decoder');
const { MeshoptDecoder } = await import(pathToFileURL(decoderPath));
await MeshoptDecoder.ready;
const MESHOPT = ['EXT_meshopt_compression', 'KHR_meshopt_compression'];
let failures = 0;
const fail = (text) => (++failures, console.log(`FAIL ${text}`));

// Whether decoded data x and y agree: exactly, or to one unit for the filters specified so.
function agree(x, y, filter, stride) {
  if (filter !== 'OCTAHEDRAL' && filter !== 'QUATERNION') return Buffer.compare(Buffer.from(x), Buffer.from(y)) === 0;
  const Type = stride === 4 ? Int8Array : Int16Array;
  const a = new Type(x.slice().buffer), b = new Type(y.slice().buffer);
  return a.length === b.length && a.every((v, k) => Math.abs(v - b[k]) <= 1);
}

async function load(file, checkFallbacks) {
  const raw = new Uint8Array(await readFile(file));
  const le32 = (at) => raw[at] | (raw[at + 1] << 8) | (raw[at + 2] << 16) | (raw[at + 3] * 2 ** 24);
  let json, bin = null;
  if (le32(0) === 0x46546c67) {
    const length = le32(12);
    json = JSON.parse(new TextDecoder().decode(raw.subarray(20, 20 + length)));
    if (20 + length < raw.length) bin = raw.subarray(28 + length, 28 + length + le32(20 + length));
  } else {
    json = JSON.parse(new TextDecoder().decode(raw));
  }
  const buffers = [];
  for (const [i, b] of (json.buffers || []).entries()) {
    if (b.uri === undefined) buffers.push(i === 0 && bin ? bin : null);
    else if (b.uri.startsWith('data:')) buffers.push(new Uint8Array(Buffer.from(b.uri.split(',')[1], 'base64')));
    else buffers.push(new Uint8Array(await readFile(path.join(path.dirname(file), decodeURIComponent(b.uri)))));
  }
  const doc = { file, json, buffers, views: [] };
  for (const [i, v] of (json.bufferViews || []).entries()) {
    const name = MESHOPT.find((n) => v.extensions && v.extensions[n]);
    const fallback = buffers[v.buffer] && buffers[v.buffer].subarray(v.byteOffset || 0, (v.byteOffset || 0) + v.byteLength);
    if (!name) {
      doc.views.push({ bytes: fallback, ext: null });
      continue;
    }
    const e = v.extensions[name];
    const source = buffers[e.buffer].subarray(e.byteOffset || 0, (e.byteOffset || 0) + e.byteLength);
    const bytes = new Uint8Array(e.count * e.byteStride);
    MeshoptDecoder.decodeGltfBuffer(bytes, e.count, e.byteStride, source, e.mode, e.filter);
    if (checkFallbacks && fallback && !agree(fallback, bytes, e.filter, e.byteStride))
      fail(`${file}: bufferViews[${i}]'s fallback data differ from what its ${name} data decode to`);
    doc.views.push({ bytes, ext: e, source });
  }
  return doc;
}

const COMPONENTS = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4, MAT2: 4, MAT3: 9, MAT4: 16 };
const TYPES = { 5120: 'Int8', 5121: 'Uint8', 5122: 'Int16', 5123: 'Uint16', 5125: 'Uint32', 5126: 'Float32' };
const SIZES = { 5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4 };

// Accessor i's stored values (not normalized), sparse values substituted.
function values(doc, i) {
  const a = doc.json.accessors[i], n = COMPONENTS[a.type], size = SIZES[a.componentType];
  const read = (bytes, at, type) => new DataView(bytes.buffer, bytes.byteOffset)[`get${TYPES[type]}`](at, true);
  const out = new Array(a.count * n).fill(0);
  if (a.bufferView !== undefined) {
    const view = doc.views[a.bufferView], stride = doc.json.bufferViews[a.bufferView].byteStride || n * size;
    for (let k = 0; k < a.count; ++k)
      for (let c = 0; c < n; ++c) out[k * n + c] = read(view.bytes, (a.byteOffset || 0) + k * stride + c * size, a.componentType);
  }
  if (a.sparse) {
    const ind = a.sparse.indices, val = a.sparse.values;
    for (let k = 0; k < a.sparse.count; ++k) {
      const at = read(doc.views[ind.bufferView].bytes, (ind.byteOffset || 0) + k * SIZES[ind.componentType], ind.componentType);
      for (let c = 0; c < n; ++c)
        out[at * n + c] = read(doc.views[val.bufferView].bytes, (val.byteOffset || 0) + (k * n + c) * size, a.componentType);
    }
  }
  return out;
}

// What uses each accessor: "meshes[0].primitives[1].attributes.NORMAL" -> index.
function uses(json) {
  const out = new Map();
  for (const [m, mesh] of (json.meshes || []).entries())
    for (const [p, prim] of mesh.primitives.entries()) {
      const at = `meshes[${m}].primitives[${p}]`;
      for (const [k, v] of Object.entries(prim.attributes)) out.set(`${at}.attributes.${k}`, v);
      if (prim.indices !== undefined) out.set(`${at}.indices`, prim.indices);
      for (const [t, target] of (prim.targets || []).entries())
        for (const [k, v] of Object.entries(target)) out.set(`${at}.targets[${t}].${k}`, v);
    }
  for (const [s, skin] of (json.skins || []).entries())
    if (skin.inverseBindMatrices !== undefined) out.set(`skins[${s}].inverseBindMatrices`, skin.inverseBindMatrices);
  for (const [a, anim] of (json.animations || []).entries())
    for (const [s, sampler] of anim.samplers.entries()) {
      out.set(`animations[${a}].samplers[${s}].input`, sampler.input);
      out.set(`animations[${a}].samplers[${s}].output`, sampler.output);
    }
  return out;
}

const SNORM = { 5120: 127, 5122: 32767 };
const unit = (a) => (a.normalized && SNORM[a.componentType]) || 1; // what 1.0 is stored as
const tolerance = (a) => (a.componentType === 5120 ? 2.5 / 127 : a.componentType === 5122 ? 2.5 / 32767 : 1e-5);

const before = await load(input), after = await load(output, true), ref = reference ? await load(reference) : null;
const usesBefore = uses(before.json), usesAfter = uses(after.json), usesRef = ref && uses(ref.json);
let compared = 0, normals = 0;
const normalViews = new Set([...usesBefore].filter(([k]) => k.endsWith('.NORMAL')).map(([, i]) => before.json.accessors[i].bufferView));
for (const [key, i] of usesBefore) {
  if (!usesAfter.has(key)) {
    if (!key.endsWith('.NORMAL')) fail(`${output}: ${key} is gone`);
    continue;
  }
  const j = usesAfter.get(key), a = before.json.accessors[i], b = after.json.accessors[j];
  const va = values(before, i), vb = values(after, j);
  if (key.endsWith('.NORMAL')) {
    ++normals;
    const s = unit(b), tol = tolerance(b);
    if (!key.includes('.targets['))
      for (let k = 0; k < b.count; ++k) {
        const len = Math.hypot(vb[3 * k] / s, vb[3 * k + 1] / s, vb[3 * k + 2] / s);
        if (Math.abs(len - 1) > 3 * tol) {
          fail(`${output}: ${key}[${k}] has length ${len}`);
          break;
        }
      }
    if (ref) {
      const r = ref.json.accessors[usesRef.get(key)], vr = values(ref, usesRef.get(key)), sr = unit(r);
      for (let k = 0; k < vb.length; ++k)
        if (Math.abs(vb[k] / s - vr[k] / sr) > tol + tolerance(r)) {
          fail(`${output}: ${key} value ${k} is ${vb[k] / s}, ${reference} has ${vr[k] / sr}`);
          break;
        }
    }
  } else {
    ++compared;
    const filter = a.bufferView !== undefined && before.views[a.bufferView].ext ? before.views[a.bufferView].ext.filter : null;
    const ulp = filter === 'OCTAHEDRAL' || filter === 'QUATERNION' ? 1 : 0;
    const same = a.componentType === b.componentType && a.type === b.type && a.count === b.count &&
      !!a.normalized === !!b.normalized && va.every((v, k) => Object.is(v, vb[k]) || Math.abs(v - vb[k]) <= ulp);
    if (!same) fail(`${output}: ${key} decodes to other values than ${input}'s`);
  }
  if (kept && a.bufferView !== undefined && before.views[a.bufferView].ext) {
    const e = before.views[a.bufferView].ext, view = b.bufferView !== undefined ? after.views[b.bufferView] : null;
    const normal = key.endsWith('.NORMAL'), same = !normalViews.has(a.bufferView);
    if (normal ? view && view.ext && view.ext.mode !== e.mode
               : !view || !view.ext || view.ext.mode !== e.mode || (same && (view.ext.filter || 'NONE') !== (e.filter || 'NONE')))
      fail(`${output}: ${key} is not compressed as in ${input} (${e.mode} ${e.filter || 'NONE'})`);
    else if (same && Buffer.compare(Buffer.from(view.source), Buffer.from(before.views[a.bufferView].source)) !== 0)
      fail(`${output}: ${key}'s compressed bytes are not the input's`);
  }
}
for (const [i, buffer] of after.buffers.entries()) {
  const ranges = [];
  for (const v of after.json.bufferViews || [])
    for (const r of [v, ...MESHOPT.map((n) => v.extensions && v.extensions[n]).filter((e) => e)])
      if (r.buffer === i) ranges.push([r.byteOffset || 0, (r.byteOffset || 0) + r.byteLength]);
  ranges.sort((x, y) => x[0] - y[0]);
  let covered = 0, end = 0;
  for (const [s, e] of ranges) (covered += Math.max(0, e - Math.max(s, end))), (end = Math.max(end, e));
  if (buffer && after.json.buffers[i].byteLength > covered + 3 * ranges.length)
    fail(`${output}: buffers[${i}] has ${after.json.buffers[i].byteLength} bytes, ${covered} of them referenced`);
}
if (plain) {
  const json = after.json, text = JSON.stringify([json.extensionsUsed, json.extensionsRequired, json.bufferViews, json.buffers]);
  if (MESHOPT.some((n) => text.includes(n))) fail(`${output}: a meshopt extension is left`);
}
console.log(`${output}: ${compared} accessors as in ${input}, ${normals} NORMAL${failures ? `, ${failures} failures` : ''}`);
process.exit(failures ? 1 : 0);
