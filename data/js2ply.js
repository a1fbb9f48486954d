#!/usr/bin/env node
// js2ply.js: converts a mesh module of the form
//   exports.positions = [[x, y, z], ...]; exports.cells = [[a, b, c], ...]
// (the npm packages "bunny" and "teapot") into a binary little-endian PLY
// (float x y z; uchar-count int vertex_indices) -- the layout sss_export_ply
// writes. Coordinates are rounded to float32, indices kept as they are.
//
// usage: node js2ply.js MODULE.js OUT.ply
// The output is written to OUT.ply.tmp and renamed, so an interrupted run
// never leaves a partial OUT.ply behind.
'use strict';

const fs = require('fs');
const path = require('path');

function die(msg) {
  process.stderr.write('js2ply.js: ' + msg + '\n');
  process.exit(1);
}

function main(argv) {
  if (argv.length !== 2) die('usage: node js2ply.js MODULE.js OUT.ply');
  const [modPath, outPath] = argv;
  let mod;
  try {
    mod = require(path.resolve(modPath));
  } catch (e) {
    die(modPath + ': cannot load: ' + e.message);
  }
  const pos = mod.positions, cells = mod.cells;
  if (!Array.isArray(pos) || !Array.isArray(cells)) die(modPath + ': no exports.positions / exports.cells arrays');
  if (pos.length === 0 || cells.length === 0) die(modPath + ': empty mesh');
  if (pos.length > 0x7fffffff) die(modPath + ': too many vertices for int indices');

  pos.forEach((p, i) => {
    if (!Array.isArray(p) || p.length !== 3 || !p.every(Number.isFinite))
      die(modPath + ': position ' + i + ' is not 3 finite numbers');
  });
  let faceBytes = 0;
  cells.forEach((c, i) => {
    if (!Array.isArray(c) || c.length < 1 || c.length > 255) die(modPath + ': cell ' + i + ' has ' + (c && c.length) + ' vertices');
    if (!c.every((v) => Number.isInteger(v) && v >= 0 && v < pos.length))
      die(modPath + ': cell ' + i + ': vertex index out of range [0, ' + pos.length + ')');
    faceBytes += 1 + 4 * c.length;
  });

  const header = Buffer.from(
    'ply\nformat binary_little_endian 1.0\n' +
      'element vertex ' + pos.length + '\nproperty float x\nproperty float y\nproperty float z\n' +
      'element face ' + cells.length + '\nproperty list uchar int vertex_indices\nend_header\n',
    'ascii'
  );
  const body = Buffer.alloc(12 * pos.length + faceBytes);
  let o = 0;
  for (const p of pos) {
    for (let k = 0; k < 3; k++) { body.writeFloatLE(p[k], o); o += 4; }
  }
  for (const c of cells) {
    body.writeUInt8(c.length, o); o += 1;
    for (const v of c) { body.writeInt32LE(v, o); o += 4; }
  }
  const tmp = outPath + '.tmp';
  fs.writeFileSync(tmp, Buffer.concat([header, body]));
  fs.renameSync(tmp, outPath);
  process.stderr.write('js2ply.js: ' + outPath + ': ' + pos.length + ' vertices, ' + cells.length + ' faces\n');
}

main(process.argv.slice(2));
