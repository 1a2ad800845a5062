#!/usr/bin/env node
// Validates glTF files with the Khronos glTF-Validator (npm: gltf-validator).
// Usage: node validate_gltf.mjs FILE...   (NODE_PATH pointing at the folder holding gltf-validator)
// One line per file: errors and warnings, the first messages of a failing file; exit 1 on any error.
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const validator = require('gltf-validator');
const severity = ['ERROR', 'WARNING', 'INFO', 'HINT'];
let failed = 0;

for (const file of process.argv.slice(2)) {
  const full = path.resolve(file);
  try {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(full)), {
      uri: path.basename(full),
      externalResourceFunction: (uri) =>
        fs.promises.readFile(path.resolve(path.dirname(full), decodeURIComponent(uri))).then((d) => new Uint8Array(d)),
    });
    const is = report.issues;
    console.log(`${is.numErrors ? 'FAIL' : 'ok  '} ${file}: ${is.numErrors} errors, ${is.numWarnings} warnings`);
    if (is.numErrors) {
      failed++;
      for (const m of is.messages.filter((m) => m.severity === 0).slice(0, 10)) {
        console.log(`     ${severity[m.severity]} ${m.code} ${m.pointer ?? ''} ${m.message}`);
      }
    }
  } catch (e) {
    failed++;
    console.log(`FAIL ${file}: ${e}`);
  }
}
const total = process.argv.length - 2;
console.log(`validator: ${total - failed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
