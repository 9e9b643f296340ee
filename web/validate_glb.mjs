// Validates .glb files with the Khronos glTF validator (npm: gltf-validator):
//   node web/validate_glb.mjs FILE.glb...
// Prints each file's errors, warnings and infos (the first few messages of each) and exits 1
// when any file has an error, 2 when a file cannot be read.
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error('usage: node web/validate_glb.mjs FILE.glb...');
  process.exit(2);
}
let failed = false;
for (const file of files) {
  let bytes;
  try {
    bytes = new Uint8Array(await readFile(file));
  } catch (e) {
    console.error(`${file}: ${e.message}`);
    process.exit(2);
  }
  const report = await validator.validateBytes(bytes, { uri: file, maxIssues: 1000 });
  const { numErrors, numWarnings, numInfos, numHints, messages } = report.issues;
  console.log(`${file}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ` +
              `${numHints} hints`);
  const severity = ['error', 'warning', 'info', 'hint'];
  const shown = new Map();
  for (const m of messages) {
    const count = shown.get(m.code) ?? 0;
    shown.set(m.code, count + 1);
    if (count < 3) console.log(`  ${severity[m.severity]} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  }
  if (numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
