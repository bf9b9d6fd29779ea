// A Manifold mesh as binary STL (float32 millimetres, normals left zero: a
// reader recomputes them), shared by manifold-export.mjs and levelset.mjs.
import fs from 'node:fs';

/// Writes `mesh` (Manifold's MeshGL) to `file`; returns its triangle count.
export function writeBinaryStl(mesh, file) {
  const triangles = mesh.triVerts.length / 3;
  const stride = mesh.numProp;
  const buffer = Buffer.alloc(84 + 50 * triangles);
  buffer.writeUInt32LE(triangles, 80);
  for (let t = 0; t < triangles; ++t) {
    const at = 84 + 50 * t;
    for (let k = 0; k < 3; ++k) {
      const v = mesh.triVerts[3 * t + k];
      for (let a = 0; a < 3; ++a) buffer.writeFloatLE(mesh.vertProperties[stride * v + a], at + 12 + 12 * k + 4 * a);
    }
  }
  fs.writeFileSync(file, buffer);
  return triangles;
}
