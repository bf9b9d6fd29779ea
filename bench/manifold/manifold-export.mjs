// Builds a Kerf document's CSG with Manifold at a chord tolerance and writes
// it as binary STL: the comparison of issue 13 (docs/benchmarks.md).
//
//   node manifold-export.mjs FILE.kerf TOLERANCE_MM OUT.stl
//
// Prints one JSON line: triangles, seconds (building and meshing, not the
// WebAssembly start or the writing).
//
// Supported nodes: box (with `round`: the hull of eight spheres, which is
// the exact rounded box), cylinder, sphere, union, difference,
// intersection, array, mirror, each with its transform (rotate about X,
// then Y, then Z, then translate: Manifold's own order). Anything else
// (blends, offsets, shells, smooth booleans) has no exact mesh boolean and
// is refused: Manifold can only approximate those by a level set.
//
// Circles get the segments a chord tolerance asks for: a polygon of n sides
// inscribed in a circle of radius r strays r(1 - cos(pi/n)) from it.
import fs from 'node:fs';
import Module from 'manifold-3d';
import { writeBinaryStl } from './stl.mjs';

const [file, toleranceText, out] = process.argv.slice(2);
if (!file || !toleranceText || !out) {
  console.error('usage: node manifold-export.mjs FILE.kerf TOLERANCE_MM OUT.stl');
  process.exit(2);
}
const tolerance = Number(toleranceText);
const doc = JSON.parse(fs.readFileSync(file, 'utf8'));

const wasm = await Module();
wasm.setup();
const { Manifold } = wasm;

function segments(radius) {
  if (!(tolerance < radius)) return 3;
  return Math.max(3, Math.ceil(Math.PI / Math.acos(1 - tolerance / radius)));
}

function place(m, node) {
  const t = node.transform || {};
  if (t.rotate) m = m.rotate(t.rotate);
  if (t.translate) m = m.translate(t.translate);
  return m;
}

function reflect(m, normal, offset) {
  const len = Math.hypot(...normal);
  const n = normal.map((x) => x / len);
  // Reflection across dot(n, p) = offset: p - 2 (dot(n, p) - offset) n.
  const a = (i, j) => (i === j ? 1 : 0) - 2 * n[i] * n[j];
  const mat = [
    a(0, 0), a(1, 0), a(2, 0), 0,
    a(0, 1), a(1, 1), a(2, 1), 0,
    a(0, 2), a(1, 2), a(2, 2), 0,
    2 * offset * n[0], 2 * offset * n[1], 2 * offset * n[2], 1,
  ];
  return m.transform(mat);
}

function build(node) {
  if (node.hidden) return null;
  const kids = () => (node.children || []).map(build).filter((m) => m !== null);
  let m;
  switch (node.type) {
    case 'box': {
      const [x, y, z] = node.size;
      const r = node.round || 0;
      if (r > 0) {
        const sphere = Manifold.sphere(r, 4 * Math.ceil(segments(r) / 4));
        const corners = [];
        for (const sx of [-1, 1]) for (const sy of [-1, 1]) for (const sz of [-1, 1])
          corners.push(sphere.translate([sx * (x / 2 - r), sy * (y / 2 - r), sz * (z / 2 - r)]));
        m = Manifold.hull(corners);
      } else {
        m = Manifold.cube([x, y, z], true);
      }
      break;
    }
    case 'cylinder':
      m = Manifold.cylinder(node.height, node.radius, node.radius, segments(node.radius), true);
      break;
    case 'sphere':
      m = Manifold.sphere(node.radius, 4 * Math.ceil(segments(node.radius) / 4));
      break;
    case 'union':
    case 'intersection':
    case 'difference': {
      if (node.blend) throw new Error(`${node.id}: a blend has no exact mesh boolean`);
      const c = kids();
      m = node.type === 'union' ? Manifold.union(c)
        : node.type === 'intersection' ? Manifold.intersection(c)
        : Manifold.difference(c[0], c.length > 1 ? Manifold.union(c.slice(1)) : Manifold.union([]));
      break;
    }
    case 'array': {
      const [child] = kids();
      const [nx, ny, nz] = node.count;
      const [dx, dy, dz] = node.step;
      const copies = [];
      for (let k = 0; k < nz; ++k) for (let j = 0; j < ny; ++j) for (let i = 0; i < nx; ++i)
        copies.push(child.translate([i * dx, j * dy, k * dz]));
      m = Manifold.union(copies);
      break;
    }
    case 'mirror': {
      const [child] = kids();
      m = Manifold.union([child, reflect(child, node.normal, node.offset || 0)]);
      break;
    }
    default:
      throw new Error(`${node.id}: ${node.type} is not a Manifold primitive or boolean`);
  }
  return place(m, node);
}

const start = process.hrtime.bigint();
const part = build(doc.root);
const mesh = part.getMesh();
const seconds = Number(process.hrtime.bigint() - start) / 1e9;

const triangles = writeBinaryStl(mesh, out);
console.log(JSON.stringify({ triangles, seconds, genus: part.genus(), volume: part.volume() }));
