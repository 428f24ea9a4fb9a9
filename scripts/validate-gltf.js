#!/usr/bin/env node
// Validates a .gltf or .glb with the Khronos glTF validator (npm gltf-validator) and exits
// non-zero when it reports any error: the check every glTF `exao bake` writes must pass.
//
// Usage: node validate-gltf.js [--modules DIR] [--missing-ok URI,...] FILE
//   --modules DIR    folder that holds node_modules/gltf-validator (scripts/install-test-tools.sh
//                    puts it in BUILD_DIR/test-tools); default: node's usual module lookup
//   --missing-ok ... image URIs that may be missing: the input scene already lacked them (the
//                    shared scenes ship without textures), so their IO_ERRORs are not the
//                    writer's fault. They are still listed, marked "ignored".
// Exit status: 0 no errors, 1 errors, 2 usage or the validator is not installed.
'use strict';
const fs = require('fs');
const path = require('path');

function usage(message) {
  console.error(`validate-gltf: ${message}`);
  process.exit(2);
}

const args = process.argv.slice(2);
let modules = null;
let missingOk = new Set();
let file = null;
while (args.length > 0) {
  const arg = args.shift();
  if (arg === '--modules') modules = args.shift();
  else if (arg === '--missing-ok') missingOk = new Set((args.shift() || '').split(',').filter((s) => s));
  else if (file === null) file = arg;
  else usage(`unexpected argument ${arg}`);
}
if (!file) usage('no file given');

let validator;
try {
  validator = modules ? require(path.join(modules, 'node_modules', 'gltf-validator')) : require('gltf-validator');
} catch (e) {
  usage('the gltf-validator package is not installed (run scripts/install-test-tools.sh)');
}

let bytes;
try {
  bytes = new Uint8Array(fs.readFileSync(file));
} catch (e) {
  usage(`${file}: cannot read: ${e.message}`);
}
const folder = path.dirname(path.resolve(file));
const severities = ['error', 'warning', 'info', 'hint'];

validator
  .validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,  // no limit
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        fs.readFile(path.join(folder, decodeURIComponent(uri)), (err, data) => {
          if (err) reject(err.toString());
          else resolve(new Uint8Array(data));
        });
      }),
  })
  .then((report) => {
    // Resources the validator could not load, by the URI it tried.
    const unloaded = new Map();
    for (const resource of report.info && report.info.resources ? report.info.resources : []) {
      if (resource.uri) unloaded.set(resource.pointer, decodeURIComponent(resource.uri));
    }
    let errors = 0;
    for (const m of report.issues.messages) {
      let note = '';
      if (m.severity === 0) {
        const uri = unloaded.get((m.pointer || '').replace(/\/uri$/, ''));
        if (m.code === 'IO_ERROR' && uri !== undefined && missingOk.has(uri)) note = ' (ignored: missing in the input too)';
        else ++errors;
      }
      console.log(`${severities[m.severity] || m.severity}: ${m.code} ${m.pointer || ''} ${m.message}${note}`);
    }
    const i = report.issues;
    console.log(`${file}: ${errors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
    process.exit(errors > 0 ? 1 : 0);
  })
  .catch((e) => {
    console.error(`validate-gltf: ${file}: ${e}`);
    process.exit(1);
  });
