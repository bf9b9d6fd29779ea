// Kerf's field in JavaScript: an evaluator of the tape that
// build/bench/kerf_tape_json writes, so that Manifold's level set
// (levelset.mjs) meshes Kerf's own exact field on the blended parts, where
// Manifold has no exact mesh boolean (issue 13).
//
//   node tape.mjs check TAPE.json...   compare with the C++ samples
//
// A port of the double-precision point path, operation for operation in
// the same order, so that it gives the same doubles (JavaScript numbers are
// IEEE doubles, Math.sqrt is correctly rounded, and the C++ build has no
// FMA contraction): the shapes of evaluator/include/kerf/evaluator/
// Primitives.hpp (extrusions and revolves as PointEvaluator.cpp's
// profileBlock computes them, which is what the double path runs), the
// combinations of Combine.hpp (std::min(a, b) is b < a ? b : a and
// std::max(a, b) is a < b ? b : a, written out, since Math.min and
// Math.max treat NaN and -0 otherwise) and the stack machine of
// evaluator/src/PointEvaluator.cpp. The check mode holds it to that: the
// samples are kerf::PointEvaluator<double>'s own values.
//
// Manifold calls the field once per grid point, hundreds of millions of
// times, so an evaluation allocates nothing: the tape is flattened into
// typed arrays once, the stack is a preallocated Float64Array, and each
// profile edge's constants are computed once (with the same operations as
// the C++ inner loop, so they are the same numbers).
import fs from 'node:fs';
import { pathToFileURL } from 'node:url';

const OPS = ['primitive', 'min', 'max', 'smooth_min', 'smooth_max', 'negate', 'offset', 'shell'];
const KINDS = ['box', 'sphere', 'cylinder', 'cone', 'torus', 'extrude', 'halfspace', 'revolve'];
const EXTRUDE = 5;
const REVOLVE = 7;

/// Builds the evaluator of a parsed tape. Returns { evaluate(x, y, z) } for
/// tape-relative points and { evaluateWorld(x, y, z) } for world points
/// (minus the tape's origin), plus the tape's bounds and origin.
export function loadTape(tape) {
  const n = tape.code.length;
  const op = new Int32Array(n);
  const shapeOf = new Int32Array(n);
  const k = new Float64Array(n);
  const invK = new Float64Array(n);
  const quarterK = new Float64Array(n);
  for (let i = 0; i < n; ++i) {
    const ins = tape.code[i];
    op[i] = OPS.indexOf(ins.op);
    if (op[i] < 0) throw new Error(`instruction ${i}: unknown op ${ins.op}`);
    shapeOf[i] = ins.shape;
    k[i] = ins.k;
    // Combine.hpp: V(S(1) / k) and V(k * S(0.25)), the same numbers here.
    invK[i] = 1 / ins.k;
    quarterK[i] = ins.k * 0.25;
  }
  const m = tape.shapes.length;
  const kind = new Int32Array(m);
  const param = new Float64Array(6 * m);
  const frame = new Float64Array(12 * m);
  // Profiles: per shape, edges [edgeStart, edgeStart + edgeCount) of the
  // flat edge arrays, in profileBlock's order (edge e runs from point e to
  // point j = e - 1, wrapping).
  const edgeStart = new Int32Array(m);
  const edgeCount = new Int32Array(m);
  const edges = [];
  for (let s = 0; s < m; ++s) {
    const sh = tape.shapes[s];
    kind[s] = KINDS.indexOf(sh.kind);
    if (kind[s] < 0 || kind[s] !== sh.kind_number) throw new Error(`shape ${s}: unknown kind ${sh.kind}`);
    for (let i = 0; i < 6; ++i) param[6 * s + i] = sh.param[i];
    for (let i = 0; i < 12; ++i) frame[12 * s + i] = sh.frame[i];
    edgeStart[s] = edges.length;
    if (kind[s] === EXTRUDE || kind[s] === REVOLVE) {
      const v = sh.polygon;
      const count = v.length;
      for (let e = 0, j = count - 1; e < count; j = e++) {
        // On the axis: inside the solid (sdf::polygon2d), no edge.
        if (kind[s] === REVOLVE && v[e][0] === 0 && v[j][0] === 0) continue;
        const vx = v[e][0], vy = v[e][1];
        const ex = v[j][0] - vx, ey = v[j][1] - vy;
        edges.push([vx, vy, ex, ey, 1 / (ex * ex + ey * ey), v[j][1]]);
      }
    }
    edgeCount[s] = edges.length - edgeStart[s];
  }
  const edge = new Float64Array(6 * edges.length);
  edges.forEach((e, i) => edge.set(e, 6 * i));
  const stack = new Float64Array(Math.max(1, tape.max_stack));
  const MAX = Number.MAX_VALUE; // std::numeric_limits<double>::max()

  // Distance of a profile (profileBlock): pu, pv are the point's profile
  // plane coordinates.
  function profile(s, pu, pv) {
    let d = MAX;
    let sign = 1;
    const end = 6 * (edgeStart[s] + edgeCount[s]);
    for (let a = 6 * edgeStart[s]; a < end; a += 6) {
      const vx = edge[a], vy = edge[a + 1], ex = edge[a + 2], ey = edge[a + 3];
      const wx = pu - vx, wy = pv - vy;
      let t = (wx * ex + wy * ey) * edge[a + 4];
      t = t < 0 ? 0 : t;
      t = 1 < t ? 1 : t;
      const bx = wx - ex * t, by = wy - ey * t;
      const dd = bx * bx + by * by;
      d = dd < d ? dd : d;
      const c1 = pv >= vy, c2 = pv < edge[a + 5], c3 = ex * wy > ey * wx;
      if ((c1 && c2 && c3) || (!c1 && !c2 && !c3)) sign = -sign;
    }
    return sign * Math.sqrt(d);
  }

  function shape(s, x, y, z) {
    const f = 12 * s;
    const lx = frame[f] * x + frame[f + 1] * y + frame[f + 2] * z + frame[f + 9];
    const ly = frame[f + 3] * x + frame[f + 4] * y + frame[f + 5] * z + frame[f + 10];
    const lz = frame[f + 6] * x + frame[f + 7] * y + frame[f + 8] * z + frame[f + 11];
    const p = 6 * s;
    switch (kind[s]) {
      case 0: { // box: bx, by, bz, round
        const qx = Math.abs(lx) - param[p], qy = Math.abs(ly) - param[p + 1], qz = Math.abs(lz) - param[p + 2];
        const mx = qx < 0 ? 0 : qx, my = qy < 0 ? 0 : qy, mz = qz < 0 ? 0 : qz;
        const outside = Math.sqrt(mx * mx + my * my + mz * mz);
        const myz = qy < qz ? qz : qy;
        const mxyz = qx < myz ? myz : qx;
        const inside = 0 < mxyz ? 0 : mxyz;
        return outside + inside - param[p + 3];
      }
      case 1: // sphere: radius
        return Math.sqrt(lx * lx + ly * ly + lz * lz) - param[p];
      case 2: { // cylinder: radius, half height
        const dr = Math.sqrt(lx * lx + ly * ly) - param[p];
        const dz = Math.abs(lz) - param[p + 1];
        const big = dr < dz ? dz : dr;
        const mr = dr < 0 ? 0 : dr, mz = dz < 0 ? 0 : dz;
        return (0 < big ? 0 : big) + Math.sqrt(mr * mr + mz * mz);
      }
      case 3: { // cone: r1, r2, h, k2x, k2y, 1 / |k2|^2
        const r1 = param[p], r2 = param[p + 1], h = param[p + 2];
        const k2x = param[p + 3], k2y = param[p + 4], invK2 = param[p + 5];
        const qx = Math.sqrt(lx * lx + ly * ly);
        const qy = lz;
        const rr = qy < 0 ? r1 : r2;
        const cax = qx - (rr < qx ? rr : qx);
        const cay = Math.abs(qy) - h;
        let t = ((r2 - qx) * k2x + (h - qy) * k2y) * invK2;
        t = t < 0 ? 0 : t;
        t = 1 < t ? 1 : t;
        const cbx = qx - r2 + k2x * t;
        const cby = qy - h + k2y * t;
        const sgn = cbx < 0 && cay < 0 ? -1 : 1;
        const da = cax * cax + cay * cay, db = cbx * cbx + cby * cby;
        return sgn * Math.sqrt(db < da ? db : da);
      }
      case 4: { // torus: major, minor
        const q = Math.sqrt(lx * lx + ly * ly) - param[p];
        return Math.sqrt(q * q + lz * lz) - param[p + 1];
      }
      case 5: { // extrude: half height; profile in (x, y)
        const d2 = profile(s, lx, ly);
        const wz = Math.abs(lz) - param[p];
        const big = d2 < wz ? wz : d2;
        const md = d2 < 0 ? 0 : d2, mz = wz < 0 ? 0 : wz;
        return (0 < big ? 0 : big) + Math.sqrt(md * md + mz * mz);
      }
      case 6: // halfspace: nx, ny, nz, offset
        return param[p] * lx + param[p + 1] * ly + param[p + 2] * lz - param[p + 3];
      case 7: // revolve: profile of (r, z)
        return profile(s, Math.sqrt(lx * lx + ly * ly), lz);
      default:
        return NaN;
    }
  }

  function evaluate(x, y, z) {
    if (n === 0) return Infinity;
    let sp = 0;
    for (let i = 0; i < n; ++i) {
      switch (op[i]) {
        case 0:
          stack[sp++] = shape(shapeOf[i], x, y, z);
          break;
        case 1: { // min
          const b = stack[--sp], a = stack[sp - 1];
          stack[sp - 1] = b < a ? b : a;
          break;
        }
        case 2: { // max
          const b = stack[--sp], a = stack[sp - 1];
          stack[sp - 1] = a < b ? b : a;
          break;
        }
        case 3: { // smooth min: min(a, b) - h h k / 4
          const b = stack[--sp], a = stack[sp - 1];
          const g = k[i] - Math.abs(a - b);
          const h = (g < 0 ? 0 : g) * invK[i];
          stack[sp - 1] = (b < a ? b : a) - h * h * quarterK[i];
          break;
        }
        case 4: { // smooth max: max(a, b) + h h k / 4
          const b = stack[--sp], a = stack[sp - 1];
          const g = k[i] - Math.abs(a - b);
          const h = (g < 0 ? 0 : g) * invK[i];
          stack[sp - 1] = (a < b ? b : a) + h * h * quarterK[i];
          break;
        }
        case 5: // negate
          stack[sp - 1] = -stack[sp - 1];
          break;
        case 6: // offset
          stack[sp - 1] = stack[sp - 1] - k[i];
          break;
        case 7: { // shell: max(a, -(a + t))
          const a = stack[sp - 1];
          const b = -(a + k[i]);
          stack[sp - 1] = a < b ? b : a;
          break;
        }
      }
    }
    return stack[0];
  }

  const [ox, oy, oz] = tape.origin;
  const bounds = tape.bounds;
  return {
    evaluate,
    evaluateWorld: (x, y, z) => evaluate(x - ox, y - oy, z - oz),
    bounds,
    origin: tape.origin,
    instructions: n,
    shapes: m,
  };
}

export function readTape(file) {
  return JSON.parse(fs.readFileSync(file, 'utf8'));
}

// The check: every C++ sample against this port.
function check(files) {
  let worst = 0;
  for (const file of files) {
    const json = readTape(file);
    const samples = json.samples || [];
    if (samples.length === 0) throw new Error(`${file}: no samples (kerf_tape_json --samples N)`);
    const tape = loadTape(json);
    let max = 0, exact = 0, at = null;
    for (const [x, y, z, f] of samples) {
      const diff = Math.abs(tape.evaluate(x, y, z) - f);
      if (diff === 0) ++exact;
      if (!(diff <= max)) { max = diff; at = [x, y, z, f]; }
    }
    // Speed: the samples again, timed (after the pass above warmed it up).
    const rounds = Math.max(1, Math.ceil(2e6 / samples.length));
    let sink = 0;
    const start = process.hrtime.bigint();
    for (let r = 0; r < rounds; ++r) for (const s of samples) sink += tape.evaluate(s[0], s[1], s[2]);
    const ns = Number(process.hrtime.bigint() - start) / (rounds * samples.length);
    console.log(JSON.stringify({
      file: json.file, instructions: tape.instructions, shapes: tape.shapes, samples: samples.length,
      max_abs_difference_mm: max, exactly_equal: exact, ns_per_evaluation: Math.round(ns),
      ...(max > 0 ? { worst_sample: at } : {}), sink: Number.isFinite(sink),
    }));
    worst = Math.max(worst, max);
  }
  return worst < 1e-9 ? 0 : 1;
}

if (process.argv[1] && import.meta.url === pathToFileURL(process.argv[1]).href) {
  const [mode, ...files] = process.argv.slice(2);
  if (mode !== 'check' || files.length === 0) {
    console.error('usage: node tape.mjs check TAPE.json...');
    process.exit(2);
  }
  process.exit(check(files));
}
