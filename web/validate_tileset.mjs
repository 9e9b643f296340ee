// Checks a 3D Tiles 1.1 tileset folder against the specification's rules for tileset.json
// (written from the specification: the JSON schema's required properties, types and ranges,
// and its rules between tiles), and each tile's .glb content with the Khronos glTF validator:
//   node web/validate_tileset.mjs DIR [--contents N]
// --contents N validates only every k-th content so that about N are (default: all).
// Prints the errors and warnings found and a summary; exits 1 on any error, 2 on bad usage.
import { readFile } from 'node:fs/promises';
import { existsSync } from 'node:fs';
import path from 'node:path';
import validator from 'gltf-validator';

const args = process.argv.slice(2);
const folder = args.find((a, i) => !a.startsWith('--') && args[i - 1] !== '--contents');
const at = args.indexOf('--contents');
const wanted = at >= 0 ? Number(args[at + 1]) : Infinity;
if (!folder || !(wanted > 0)) {
  console.error('usage: node web/validate_tileset.mjs DIR [--contents N]');
  process.exit(2);
}

const errors = [], warnings = [];
const error = (where, text) => errors.push(`${where}: ${text}`);
const warn = (where, text) => warnings.push(`${where}: ${text}`);
const isNumber = (v) => typeof v === 'number' && Number.isFinite(v);

let tileset;
try {
  tileset = JSON.parse(await readFile(path.join(folder, 'tileset.json'), 'utf8'));
} catch (e) {
  console.error(`${folder}: ${e.message}`);
  process.exit(1);
}

// asset: required, with a version of 1.0 or 1.1.
if (typeof tileset.asset !== 'object') error('/asset', 'missing');
else if (!['1.0', '1.1'].includes(tileset.asset.version))
  error('/asset/version', `"${tileset.asset.version}" is not 1.0 or 1.1`);
if (!isNumber(tileset.geometricError) || tileset.geometricError < 0)
  error('/geometricError', 'missing or negative');
if (typeof tileset.root !== 'object') error('/root', 'missing');

// A box is 12 numbers: a centre and three half-axes; a point is inside when its coordinates
// along each half-axis are within +-1.
function boxCorners(box) {
  const [cx, cy, cz, ...h] = box;
  const corners = [];
  for (let i = 0; i < 8; ++i) {
    const s = [i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1];
    corners.push([0, 1, 2].map((k) => [cx, cy, cz][k] + s[0] * h[k] + s[1] * h[3 + k] + s[2] * h[6 + k]));
  }
  return corners;
}
function insideBox(box, p, slack) {
  const c = box.slice(0, 3);
  for (let a = 0; a < 3; ++a) {
    const axis = box.slice(3 + 3 * a, 6 + 3 * a);
    const length2 = axis.reduce((s, v) => s + v * v, 0);
    const d = [0, 1, 2].reduce((s, k) => s + (p[k] - c[k]) * axis[k], 0) / length2;
    if (Math.abs(d) > 1 + slack) return false;
  }
  return true;
}

function checkVolume(where, volume) {
  if (typeof volume !== 'object') return error(where, 'boundingVolume missing');
  const kinds = ['box', 'region', 'sphere'].filter((k) => k in volume);
  if (kinds.length !== 1) return error(where, 'boundingVolume needs exactly one of box, region, sphere');
  const lengths = { box: 12, region: 6, sphere: 4 };
  const v = volume[kinds[0]];
  if (!Array.isArray(v) || v.length !== lengths[kinds[0]] || !v.every(isNumber))
    error(where, `boundingVolume.${kinds[0]} must be ${lengths[kinds[0]]} numbers`);
  if (kinds[0] === 'sphere' && v[3] < 0) error(where, 'sphere radius negative');
}

const contents = [];
let tiles = 0, maxDepth = 0;
function checkTile(tile, where, parent, depth) {
  ++tiles;
  maxDepth = Math.max(maxDepth, depth);
  checkVolume(where, tile.boundingVolume);
  if (!isNumber(tile.geometricError) || tile.geometricError < 0)
    error(where, 'geometricError missing or negative');
  if ('refine' in tile && !['ADD', 'REPLACE'].includes(tile.refine))
    error(where, `refine "${tile.refine}" is not ADD or REPLACE`);
  if (!parent && !('refine' in tile)) error(where, 'the root tile needs refine');
  if (parent && tile.geometricError > parent.geometricError)
    warn(where, `geometricError ${tile.geometricError} above its parent's ${parent.geometricError}`);
  if (parent && tile.boundingVolume?.box && parent.boundingVolume?.box) {
    const size = Math.hypot(...parent.boundingVolume.box.slice(3));
    const outside = boxCorners(tile.boundingVolume.box)
      .filter((p) => !insideBox(parent.boundingVolume.box, p, 1e-3 + 1e-4 * size));
    if (outside.length) warn(where, 'bounding box reaches outside its parent\'s');
  }
  if ('content' in tile) {
    if (typeof tile.content.uri !== 'string') error(`${where}/content`, 'uri missing');
    else if (!existsSync(path.join(folder, tile.content.uri)))
      error(`${where}/content`, `${tile.content.uri} does not exist`);
    else contents.push(tile.content.uri);
    if (tile.content.boundingVolume) checkVolume(`${where}/content`, tile.content.boundingVolume);
  }
  if ('children' in tile) {
    if (!Array.isArray(tile.children) || tile.children.length === 0)
      error(where, 'children must be a non-empty array');
    else tile.children.forEach((c, i) => checkTile(c, `${where}/children/${i}`, tile, depth + 1));
  }
}
if (typeof tileset.root === 'object') {
  checkTile(tileset.root, '/root', null, 0);
  if (tileset.root.geometricError > tileset.geometricError)
    warn('/root', 'geometricError above the tileset\'s');
}

// The contents: glb files the glTF validator passes.
const step = Math.max(1, Math.ceil(contents.length / wanted));
let validated = 0;
for (let i = 0; i < contents.length; i += step) {
  const file = path.join(folder, contents[i]);
  const report = await validator.validateBytes(new Uint8Array(await readFile(file)), { uri: file });
  ++validated;
  for (const m of report.issues.messages.filter((m) => m.severity === 0).slice(0, 3))
    error(contents[i], `${m.code} ${m.pointer ?? ''}: ${m.message}`);
}

for (const e of errors.slice(0, 20)) console.log(`error ${e}`);
for (const w of warnings.slice(0, 20)) console.log(`warning ${w}`);
console.log(`${folder}: ${errors.length} errors, ${warnings.length} warnings; ${tiles} tiles, ` +
            `${maxDepth + 1} levels, ${contents.length} contents (${validated} validated)`);
process.exit(errors.length ? 1 : 0);
