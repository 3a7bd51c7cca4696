#!/usr/bin/env node
// Validates .glb/.gltf files with the Khronos glTF-Validator (npm package gltf-validator).
// Usage: node validate.js [--json REPORT.json] FILE...
// Prints one line per file (errors, warnings, infos, hints) and the first issues of each
// severity; exits 1 if any file has an error (or cannot be read), 0 otherwise.
'use strict';
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

const severityNames = ['error', 'warning', 'info', 'hint'];

async function validateFile(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,   // report every issue
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)), (err, data) =>
          err ? reject(err.toString()) : resolve(new Uint8Array(data)));
      }),
  });
  return report;
}

async function main() {
  const args = process.argv.slice(2);
  let jsonOut = null;
  const files = [];
  for (let i = 0; i < args.length; ++i) {
    if (args[i] === '--json') jsonOut = args[++i];
    else files.push(args[i]);
  }
  if (files.length === 0) {
    console.error('usage: node validate.js [--json REPORT.json] FILE...');
    process.exit(2);
  }
  let failed = 0;
  const summary = [];
  for (const file of files) {
    let report;
    try {
      report = await validateFile(file);
    } catch (e) {
      console.log(`${file}: cannot validate: ${e}`);
      ++failed;
      summary.push({ file, failure: String(e) });
      continue;
    }
    const issues = report.issues;
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
                `${issues.numInfos} infos, ${issues.numHints} hints`);
    // Show up to 5 distinct codes per severity (errors and warnings).
    for (const severity of [0, 1]) {
      const seen = new Map();
      for (const m of issues.messages) {
        if (m.severity !== severity) continue;
        if (!seen.has(m.code)) seen.set(m.code, { count: 0, example: m });
        seen.get(m.code).count++;
      }
      let shown = 0;
      for (const [code, { count, example }] of seen) {
        if (shown++ >= 5) break;
        console.log(`  ${severityNames[severity]} ${code} x${count}: ${example.message} at ${example.pointer || ''}`);
      }
    }
    if (issues.numErrors > 0) ++failed;
    summary.push({ file, errors: issues.numErrors, warnings: issues.numWarnings,
                   infos: issues.numInfos, hints: issues.numHints });
  }
  if (jsonOut) fs.writeFileSync(jsonOut, JSON.stringify(summary, null, 2));
  process.exit(failed > 0 ? 1 : 0);
}

main().catch((e) => { console.error(e); process.exit(1); });
