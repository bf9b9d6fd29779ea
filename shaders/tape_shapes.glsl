// The primitives of tape.glsl, written once for T (float values, vec4 duals
// and vec2 intervals), in the order of operations of the sdf:: templates
// (evaluator/include/kerf/evaluator/Primitives.hpp) and the combine:: rules
// (Combine.hpp), so that float evaluation is bit for bit C++'s. Included
// only by tape.glsl, which defines T, cT(c) (a constant as T) and, for
// intervals, KERF_TAPE_INTERVALS.
//
// Every operation between two T goes through the *T functions (addT, subT,
// negT, scaleT by a float, ...): for values and duals they are the plain
// operators, for intervals outward-rounded interval arithmetic, so one text
// serves all three. The shapes that branch on the point (cone, polygon
// profiles) have no natural interval extension and are left out of the
// interval instance: enclosureT (at the end) encloses them by containment,
// as primitive::*::enclosure does in C++. A new shape kind is a function
// here, its line in shapeT, and its line in branchFreeShapeT (intervals
// through the same formula) or, when it branches on the point, in enclosureT.

T clamp01T(T v) { return minT(maxT(v, cT(0.0)), cT(1.0)); }

T boxT(T x, T y, T z, float bx, float by, float bz, float round)
{
    const T qx = subT(absT(x), cT(bx)), qy = subT(absT(y), cT(by)), qz = subT(absT(z), cT(bz));
    const T outside = sqrtT(addT(addT(sqT(maxT(qx, cT(0.0))), sqT(maxT(qy, cT(0.0)))), sqT(maxT(qz, cT(0.0)))));
    const T inside = minT(maxT(qx, maxT(qy, qz)), cT(0.0));
    return subT(addT(outside, inside), cT(round));
}

T sphereT(T x, T y, T z, float radius) { return subT(sqrtT(addT(addT(sqT(x), sqT(y)), sqT(z))), cT(radius)); }

T cylinderT(T x, T y, T z, float radius, float halfHeight)
{
    const T dr = subT(sqrtT(addT(sqT(x), sqT(y))), cT(radius));
    const T dz = subT(absT(z), cT(halfHeight));
    return addT(minT(maxT(dr, dz), cT(0.0)), sqrtT(addT(sqT(maxT(dr, cT(0.0))), sqT(maxT(dz, cT(0.0))))));
}

T torusT(T x, T y, T z, float major, float minor)
{
    const T q = subT(sqrtT(addT(sqT(x), sqT(y))), cT(major));
    return subT(sqrtT(addT(sqT(q), sqT(z))), cT(minor));
}

T halfspaceT(T x, T y, T z, float nx, float ny, float nz, float offset)
{
    return subT(addT(addT(scaleT(x, nx), scaleT(y, ny)), scaleT(z, nz)), cT(offset));
}

T extrusionT(T d2, T z, float halfHeight)
{
    const T wz = subT(absT(z), cT(halfHeight));
    return addT(minT(maxT(d2, wz), cT(0.0)), sqrtT(addT(sqT(maxT(d2, cT(0.0))), sqT(maxT(wz, cT(0.0))))));
}

// Local coordinates of tile-relative p by the frame at word f. For
// intervals p is the box's extent per axis; for duals, tape.glsl gives each
// coordinate its row of the frame as its gradient.
void localT(uint t, uint f, T px, T py, T pz, out T lx, out T ly, out T lz)
{
    lx = addT(addT(addT(scaleT(px, tapeFloat(t, f)), scaleT(py, tapeFloat(t, f + 1u))), scaleT(pz, tapeFloat(t, f + 2u))),
              cT(tapeFloat(t, f + 9u)));
    ly = addT(addT(addT(scaleT(px, tapeFloat(t, f + 3u)), scaleT(py, tapeFloat(t, f + 4u))), scaleT(pz, tapeFloat(t, f + 5u))),
              cT(tapeFloat(t, f + 10u)));
    lz = addT(addT(addT(scaleT(px, tapeFloat(t, f + 6u)), scaleT(py, tapeFloat(t, f + 7u))), scaleT(pz, tapeFloat(t, f + 8u))),
              cT(tapeFloat(t, f + 11u)));
}

// The kinds whose formula does not branch on the point: the same call for
// values, duals and intervals (their natural extension). False for the others.
bool branchFreeShapeT(uint t, uint s, T x, T y, T z, out T r)
{
    const uint a = s + KERF_TAPE_SHAPE_PARAMS;
    const uint kind = tapeWord(t, s);
    if (kind == KERF_SHAPE_BOX)
        r = boxT(x, y, z, tapeFloat(t, a), tapeFloat(t, a + 1u), tapeFloat(t, a + 2u), tapeFloat(t, a + 3u));
    else if (kind == KERF_SHAPE_SPHERE) r = sphereT(x, y, z, tapeFloat(t, a));
    else if (kind == KERF_SHAPE_CYLINDER) r = cylinderT(x, y, z, tapeFloat(t, a), tapeFloat(t, a + 1u));
    else if (kind == KERF_SHAPE_TORUS) r = torusT(x, y, z, tapeFloat(t, a), tapeFloat(t, a + 1u));
    else if (kind == KERF_SHAPE_HALFSPACE)
        r = halfspaceT(x, y, z, tapeFloat(t, a), tapeFloat(t, a + 1u), tapeFloat(t, a + 2u), tapeFloat(t, a + 3u));
    else return false;
    return true;
}

#ifndef KERF_TAPE_INTERVALS

T coneT(T x, T y, T z, float r1, float r2, float h, float k2x, float k2y, float invK2)
{
    const T qx = sqrtT(addT(sqT(x), sqT(y)));
    const T qy = z;
    const float rr = valT(qy) < 0.0 ? r1 : r2;
    const T cax = subT(qx, minT(qx, cT(rr)));
    const T cay = subT(absT(qy), cT(h));
    const T t = clamp01T(scaleT(addT(scaleT(subT(cT(r2), qx), k2x), scaleT(subT(cT(h), qy), k2y)), invK2));
    const T cbx = addT(subT(qx, cT(r2)), scaleT(t, k2x));
    const T cby = addT(subT(qy, cT(h)), scaleT(t, k2y));
    const float s = (valT(cbx) < 0.0 && valT(cay) < 0.0) ? -1.0 : 1.0;
    return scaleT(sqrtT(minT(addT(sqT(cax), sqT(cay)), addT(sqT(cbx), sqT(cby)))), s);
}

#ifdef KERF_TAPE_DUALS
// sdf::polygon2d's form for duals (Primitives.hpp, which says why): the
// nearest edge in plain floats, then the gradient once, from it: the edge's
// outward normal where the nearest point lies inside the edge, the signed
// (p - q) / |p - q| where it is a vertex q. The value is the generic form's.
vec4 polygonDual(uint t, uint first, uint count, vec4 x, vec4 y, bool axisEdges)
{
    const float px = x.x, py = y.x;
    float d = kTapeFloatMax, qx = 0.0, qy = 0.0, edgeX = 0.0, edgeY = 0.0, area = 0.0;
    if (axisEdges) {
        qx = px - tapeFloat(t, first);
        qy = py - tapeFloat(t, first + 1u);
        d = qx * qx + qy * qy;
    }
    bool inside = false;
    for (uint i = 0u, j = count - 1u; i < count; j = i++) {
        const float vix = tapeFloat(t, first + 2u * i), viy = tapeFloat(t, first + 2u * i + 1u);
        const float vjx = tapeFloat(t, first + 2u * j), vjy = tapeFloat(t, first + 2u * j + 1u);
        area += vjx * viy - vix * vjy;
        if (!axisEdges && vix == 0.0 && vjx == 0.0) continue;
        const float ex = vjx - vix, ey = vjy - viy;
        const float wx = px - vix, wy = py - viy;
        const float raw = (wx * ex + wy * ey) / (ex * ex + ey * ey);
        const float s = min(max(raw, 0.0), 1.0);
        const float bx = wx - s * ex, by = wy - s * ey;
        const float di = bx * bx + by * by;
        if (di < d) {
            d = di;
            qx = bx;
            qy = by;
            const bool within = 0.0 < raw && raw < 1.0;
            edgeX = within ? ex : 0.0;
            edgeY = within ? ey : 0.0;
        }
        const bool c1 = py >= viy, c2 = py < vjy, c3 = ex * wy > ey * wx;
        if ((c1 && c2 && c3) || (!c1 && !c2 && !c3)) inside = !inside;
    }
    const float dist = sqrt(d);
    vec2 g = vec2(0.0);
    if (edgeX != 0.0 || edgeY != 0.0)
        g = vec2(-edgeY, edgeX) * ((area < 0.0 ? -1.0 : 1.0) / sqrt(edgeX * edgeX + edgeY * edgeY));
    else if (dist > 0.0)
        g = vec2(qx, qy) * ((inside ? -1.0 : 1.0) / dist);
    return vec4(inside ? -dist : dist, g.x * x.yzw + g.y * y.yzw);
}
#endif

// sdf::polygon2d over the `count` points (x, y floats) from word `first`;
// without a revolve's edges on the axis when axisEdges is false.
T polygonT(uint t, uint first, uint count, T x, T y, bool axisEdges)
{
#ifdef KERF_TAPE_DUALS
    return polygonDual(t, first, count, x, y, axisEdges);
#else
    T d = axisEdges ? addT(sqT(subT(x, cT(tapeFloat(t, first)))), sqT(subT(y, cT(tapeFloat(t, first + 1u)))))
                    : cT(kTapeFloatMax);
    bool inside = false;
    for (uint i = 0u, j = count - 1u; i < count; j = i++) {
        const float vix = tapeFloat(t, first + 2u * i), viy = tapeFloat(t, first + 2u * i + 1u);
        const float vjx = tapeFloat(t, first + 2u * j), vjy = tapeFloat(t, first + 2u * j + 1u);
        if (!axisEdges && vix == 0.0 && vjx == 0.0) continue;
        const float ex = vjx - vix, ey = vjy - viy;
        const T wx = subT(x, cT(vix)), wy = subT(y, cT(viy));
        const T s = clamp01T(divT(addT(scaleT(wx, ex), scaleT(wy, ey)), ex * ex + ey * ey));
        d = minT(d, addT(sqT(subT(wx, scaleT(s, ex))), sqT(subT(wy, scaleT(s, ey)))));
        const bool c1 = valT(y) >= viy, c2 = valT(y) < vjy, c3 = ex * valT(wy) > ey * valT(wx);
        if ((c1 && c2 && c3) || (!c1 && !c2 && !c3)) inside = !inside;
    }
    const T dist = sqrtT(d);
    return inside ? negT(dist) : dist;
#endif
}

// sdf::revolution: the profile's [r, z] points at (length(x, y), z).
T revolutionT(uint t, uint first, uint count, T x, T y, T z)
{
    return polygonT(t, first, count, sqrtT(addT(sqT(x), sqT(y))), z, false);
}

// The shape at word s, at local point (x, y, z). NaN for a kind not named here.
// One chain of every kind, not branchFreeShapeT and then the rest: the
// tracer's hybrid refinement runs this for every pixel it refines, and the
// split cost it 3 % on the H100 (docs/benchmarks.md).
T shapeT(uint t, uint s, T x, T y, T z)
{
    const uint a = s + KERF_TAPE_SHAPE_PARAMS;
    const uint kind = tapeWord(t, s);
    if (kind == KERF_SHAPE_BOX)
        return boxT(x, y, z, tapeFloat(t, a), tapeFloat(t, a + 1u), tapeFloat(t, a + 2u), tapeFloat(t, a + 3u));
    if (kind == KERF_SHAPE_SPHERE) return sphereT(x, y, z, tapeFloat(t, a));
    if (kind == KERF_SHAPE_CYLINDER) return cylinderT(x, y, z, tapeFloat(t, a), tapeFloat(t, a + 1u));
    if (kind == KERF_SHAPE_CONE)
        return coneT(x, y, z, tapeFloat(t, a), tapeFloat(t, a + 1u), tapeFloat(t, a + 2u), tapeFloat(t, a + 3u),
                     tapeFloat(t, a + 4u), tapeFloat(t, a + 5u));
    if (kind == KERF_SHAPE_TORUS) return torusT(x, y, z, tapeFloat(t, a), tapeFloat(t, a + 1u));
    if (kind == KERF_SHAPE_EXTRUDE)
        return extrusionT(polygonT(t, tapeWord(t, a + 1u), tapeWord(t, a + 2u), x, y, true), z, tapeFloat(t, a));
    if (kind == KERF_SHAPE_HALFSPACE)
        return halfspaceT(x, y, z, tapeFloat(t, a), tapeFloat(t, a + 1u), tapeFloat(t, a + 2u), tapeFloat(t, a + 3u));
    if (kind == KERF_SHAPE_REVOLVE) return revolutionT(t, tapeWord(t, a + 1u), tapeWord(t, a + 2u), x, y, z);
    tapeUnknownKind = true;
    return cT(kTapeNaN);
}

// The spec's polynomial smooth minimum and its mirror (combine::smoothMin,
// smoothMax), and the shell (combine::shell). Intervals have their own
// (monotone and convex: tape.glsl takes them at the ends).
T smoothMinT(T a, T b, float k)
{
    const T h = scaleT(maxT(subT(cT(k), absT(subT(a, b))), cT(0.0)), 1.0 / k);
    return subT(minT(a, b), scaleT(sqT(h), k * 0.25));
}
T smoothMaxT(T a, T b, float k)
{
    const T h = scaleT(maxT(subT(cT(k), absT(subT(a, b))), cT(0.0)), 1.0 / k);
    return addT(maxT(a, b), scaleT(sqT(h), k * 0.25));
}
T shellT(T a, float thickness) { return maxT(a, negT(addT(a, cT(thickness)))); }

// The primitive at word s over the tape-relative point (px, py, pz).
T primitiveT(uint t, uint s, T px, T py, T pz)
{
    T x, y, z;
    localT(t, s + KERF_TAPE_SHAPE_FRAME, px, py, pz, x, y, z);
    return shapeT(t, s, x, y, z);
}

#endif

#ifdef KERF_TAPE_INTERVALS

// The enclosures of primitive::*::enclosure (Primitives.hpp) over the box
// (x, y, z) of the shape's local frame: the natural extension where the
// formula does not branch, else a containment (a solid inside another has a
// field at least as large everywhere, one containing another at most as
// large). NaN for a kind not named here.
void polygonBounds(uint t, uint first, uint count, out vec2 lo, out vec2 hi)
{
    lo = vec2(kTapeInf);
    hi = vec2(-kTapeInf);
    for (uint i = 0u; i < count; ++i) {
        const vec2 v = vec2(tapeFloat(t, first + 2u * i), tapeFloat(t, first + 2u * i + 1u));
        lo = min(lo, v);
        hi = max(hi, v);
    }
}
vec2 enclosureT(uint t, uint s, vec2 x, vec2 y, vec2 z)
{
    vec2 r;
    if (branchFreeShapeT(t, s, x, y, z, r)) return r;
    const uint a = s + KERF_TAPE_SHAPE_PARAMS;
    const uint kind = tapeWord(t, s);
    if (kind == KERF_SHAPE_CONE) {
        // Between the cylinders of its larger and its smaller radius.
        const float r1 = tapeFloat(t, a), r2 = tapeFloat(t, a + 1u), h = tapeFloat(t, a + 2u);
        return vec2(cylinderT(x, y, z, max(r1, r2), h).x, cylinderT(x, y, z, min(r1, r2), h).y);
    }
    if (kind == KERF_SHAPE_EXTRUDE) {
        // Inside its profile's bounding box swept over its height.
        vec2 lo, hi;
        polygonBounds(t, tapeWord(t, a + 1u), tapeWord(t, a + 2u), lo, hi);
        const vec2 mid = 0.5 * (lo + hi), halfSize = 0.5 * (hi - lo);
        return vec2(boxT(subT(x, cT(mid.x)), subT(y, cT(mid.y)), z, halfSize.x, halfSize.y, tapeFloat(t, a), 0.0).x, kTapeInf);
    }
    if (kind == KERF_SHAPE_REVOLVE) {
        // Inside the cylinder of its largest radius over its height.
        vec2 lo, hi;
        polygonBounds(t, tapeWord(t, a + 1u), tapeWord(t, a + 2u), lo, hi);
        const float zMid = 0.5 * (lo.y + hi.y), halfHeight = 0.5 * (hi.y - lo.y);
        return vec2(cylinderT(x, y, subT(z, cT(zMid)), max(hi.x, 0.0), halfHeight).x, kTapeInf);
    }
    tapeUnknownKind = true;
    return cT(kTapeNaN);
}

#endif
