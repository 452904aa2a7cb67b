#!/usr/bin/env node
// Runs the Khronos glTF-Validator on GLB files: one line per file with error and warning
// counts, then the messages. Exits 1 if any file has errors (or cannot be read), or if a file
// with skins (the validator's `info.hasSkins`) has warnings: our skinned layout is meant to pass
// with none, and its warnings (a skinned mesh node with a parent or a transformation, joints
// with zero weight) are what make Blender, Godot and three.js pose it wrongly.
// Setup: npm install gltf-validator (set NODE_PATH if it is installed elsewhere).
// Usage: node .ci/validate-gltf.js a.glb b.glb ...
'use strict';
const fs = require('fs');
const validator = require('gltf-validator');

async function main(files) {
  if (files.length === 0) {
    console.error('usage: node validate-gltf.js FILE.glb...');
    return 2;
  }
  let failed = false;
  for (const file of files) {
    let report;
    try {
      report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
        uri: file,
        maxIssues: 0,
      });
    } catch (e) {
      console.log(`${file}: cannot validate: ${e.message || e}`);
      failed = true;
      continue;
    }
    const issues = report.issues;
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
      `${issues.numInfos} infos, ${issues.numHints} hints`);
    const severity = ['error', 'warning', 'info', 'hint'];
    for (const m of issues.messages) {
      console.log(`  ${severity[m.severity] || m.severity} ${m.code} ${m.pointer || ''}: ${m.message}`);
    }
    const strict = Boolean(report.info && report.info.hasSkins);
    if (issues.numErrors > 0 || (strict && issues.numWarnings > 0)) {
      if (strict && issues.numWarnings > 0) {
        console.log(`  ${file} has skins, so its warnings fail the check too`);
      }
      failed = true;
    }
  }
  return failed ? 1 : 0;
}

main(process.argv.slice(2)).then((code) => process.exit(code), (e) => {
  console.error(e);
  process.exit(1);
});
