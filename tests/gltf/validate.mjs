// Validates glTF files with the Khronos glTF-Validator (npm gltf-validator).
//   node validate.mjs NODE_MODULES_DIR FILE            prints FILE's issues as JSON
//   node validate.mjs NODE_MODULES_DIR INPUT OUTPUT... also checks that no OUTPUT has an
//       error, warning or information code that INPUT does not have; exit status 1 when one does.
//   --allow CODE (before INPUT, repeatable): CODE is expected in the outputs.
// NODE_MODULES_DIR holds gltf-validator (.ci/setup installs it into build-node/).
import { readFile } from 'node:fs/promises';
import { createRequire } from 'node:module';
import path from 'node:path';

const args = process.argv.slice(2);
const allowed = [];
for (let i; (i = args.indexOf('--allow')) >= 0; ) allowed.push(...args.splice(i, 2).slice(1));
const [modules, input, ...outputs] = args;
const validator = createRequire(path.join(path.resolve(modules), 'x.js'))('gltf-validator');

async function validate(file) {
  const folder = path.dirname(file);
  const report = await validator.validateBytes(new Uint8Array(await readFile(file)), {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: async (uri) =>
      new Uint8Array(await readFile(path.join(folder, decodeURIComponent(uri)))),
  });
  const messages = report.issues.messages.filter((m) => m.severity <= 2); // 0 error, 1 warning, 2 information
  const codes = (severity) => [...new Set(messages.filter((m) => m.severity === severity).map((m) => m.code))].sort();
  return {
    file,
    errors: codes(0),
    warnings: codes(1),
    infos: codes(2),
    messages: messages.map((m) => `${m.code} ${m.pointer || ''} ${m.message}`),
  };
}

const before = await validate(input);
console.log(JSON.stringify(before));
let failed = false;
for (const output of outputs) {
  const after = await validate(output);
  const known = new Set([...before.errors, ...before.warnings, ...before.infos, ...allowed]);
  const added = [...after.errors, ...after.warnings, ...after.infos].filter((c) => !known.has(c));
  if (added.length) {
    failed = true;
    console.log(`FAIL ${output}: new issues ${added.join(' ')} (not in ${input})`);
    for (const m of after.messages) if (added.includes(m.split(' ')[0])) console.log(`  ${m}`);
  }
}
// exitCode, not exit(): exit() drops what is still queued for a pipe (a report over 64 KB was cut off).
process.exitCode = failed ? 1 : 0;
