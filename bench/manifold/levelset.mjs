// Manifold's answer for a blended Kerf part: a level set of Kerf's own
// exact field (tape.mjs, the JavaScript port of Kerf's double-precision
// evaluator) at an edge length, written as binary STL in millimetres.
// Manifold has no exact mesh boolean for smooth unions, offsets or shells
// (manifold-export.mjs refuses them); Manifold.levelSet is what it offers
// instead (issue 13; compare-blended.sh).
//
//   node levelset.mjs TAPE.json EDGE_MM OUT.stl [VERTEX_TOLERANCE_MM]
//   node levelset.mjs TAPE.json EDGE_MM --estimate
//
// TAPE.json: build/bench/kerf_tape_json FILE.kerf. Prints one JSON line:
// triangles, seconds (the level set and its mesh, not the WebAssembly
// start or the writing), edge_mm, grid (points per axis of each of the two
// cubic lattices of Manifold's body-centred grid), voxels (the dense grid
// Manifold allocates, 8 bytes each), evaluations (calls of the field),
// genus. --estimate prints grid and voxels without meshing (the script
// uses them to skip grids that would not finish in its time).
//
// The grid covers the part's bounds padded by two edges, so that the solid
// never meets the grid's boundary (where Manifold closes it off with its
// egg-crate). Signs: Manifold's level set is inside where the function is
// POSITIVE, Kerf's field where it is negative, so Manifold gets minus
// Kerf's field, at level 0. VERTEX_TOLERANCE_MM is Manifold's `tolerance`
// argument: each vertex is put within it of the surface by root finding
// along its grid edge, instead of Manifold's default linear interpolation
// between the two grid values (default 0.001 mm: the vertices are on the
// surface, what is left is the level set's own faceting; it costs a few
// more evaluations per vertex, a small share of the grid's).
import Module from 'manifold-3d';
import { loadTape, readTape } from './tape.mjs';
import { writeBinaryStl } from './stl.mjs';

const [file, edgeText, out, toleranceText] = process.argv.slice(2);
if (!file || !edgeText || !out) {
  console.error('usage: node levelset.mjs TAPE.json EDGE_MM OUT.stl [VERTEX_TOLERANCE_MM]\n' +
                '       node levelset.mjs TAPE.json EDGE_MM --estimate');
  process.exit(2);
}
const edge = Number(edgeText);
const vertexTolerance = toleranceText === undefined ? 0.001 : Number(toleranceText);
const tape = loadTape(readTape(file));
if (!tape.bounds || tape.bounds.min.some((v) => v === null) || tape.bounds.max.some((v) => v === null))
  throw new Error(`${file}: the part is empty or unbounded`);
const bounds = {
  min: tape.bounds.min.map((v) => v - 2 * edge),
  max: tape.bounds.max.map((v) => v + 2 * edge),
};

// Manifold's grid (src/sdf.cpp, Manifold::LevelSet): gridSize points per
// axis, and a dense array of voxels indexed by bits, the y and z counts
// (plus 2) rounded up to powers of two, times 2 lattices.
const grid = bounds.min.map((lo, a) => Math.floor((bounds.max[a] - lo) / edge + 1));
const pow = grid.map((g) => Math.ceil(Math.log2(g + 3)));
const voxels = (grid[0] + 2) * 2 ** (1 + pow[1] + pow[2]);

if (out === '--estimate') {
  console.log(JSON.stringify({ edge_mm: edge, grid, voxels, voxel_bytes: 8 * voxels }));
  process.exit(0);
}

const wasm = await Module();
wasm.setup();
const { Manifold } = wasm;

const evaluateWorld = tape.evaluateWorld;
let evaluations = 0;
const sdf = (p) => {
  ++evaluations;
  return -evaluateWorld(p[0], p[1], p[2]);
};

const start = process.hrtime.bigint();
const part = Manifold.levelSet(sdf, bounds, edge, 0, vertexTolerance);
const mesh = part.getMesh();
const seconds = Number(process.hrtime.bigint() - start) / 1e9;

const triangles = writeBinaryStl(mesh, out);
console.log(JSON.stringify({
  triangles, seconds, edge_mm: edge, vertex_tolerance_mm: vertexTolerance, grid, voxels, evaluations,
  genus: part.genus(), status: part.status(),
}));
