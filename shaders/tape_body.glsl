// The primitives and the stack machine of tape.glsl, written once for T
// (float values or vec4 duals), in the order of operations of the sdf::
// templates (evaluator/include/kerf/evaluator/Primitives.hpp) and the
// combine:: rules (Combine.hpp). Included only by tape.glsl, which defines
// T, cT(c) (a constant as T) and KERF_TAPE_EVALUATE (the stack machine's
// name), and KERF_TAPE_FEATURES where the deciding feature is tracked.
// Everything arithmetic between two T goes through the *T functions;
// + and - and scaling by a float are the same for both.

T clamp01T(T v) { return minT(maxT(v, cT(0.0)), cT(1.0)); }

T boxT(T x, T y, T z, float bx, float by, float bz, float round)
{
    const T qx = absT(x) - cT(bx), qy = absT(y) - cT(by), qz = absT(z) - cT(bz);
    const T outside = sqrtT(sqT(maxT(qx, cT(0.0))) + sqT(maxT(qy, cT(0.0))) + sqT(maxT(qz, cT(0.0))));
    const T inside = minT(maxT(qx, maxT(qy, qz)), cT(0.0));
    return outside + inside - cT(round);
}

T sphereT(T x, T y, T z, float radius) { return sqrtT(sqT(x) + sqT(y) + sqT(z)) - cT(radius); }

T cylinderT(T x, T y, T z, float radius, float halfHeight)
{
    const T dr = sqrtT(sqT(x) + sqT(y)) - cT(radius);
    const T dz = absT(z) - cT(halfHeight);
    return minT(maxT(dr, dz), cT(0.0)) + sqrtT(sqT(maxT(dr, cT(0.0))) + sqT(maxT(dz, cT(0.0))));
}

T torusT(T x, T y, T z, float major, float minor)
{
    const T q = sqrtT(sqT(x) + sqT(y)) - cT(major);
    return sqrtT(sqT(q) + sqT(z)) - cT(minor);
}

T halfspaceT(T x, T y, T z, float nx, float ny, float nz, float offset) { return x * nx + y * ny + z * nz - cT(offset); }

T coneT(T x, T y, T z, float r1, float r2, float h, float k2x, float k2y, float invK2)
{
    const T qx = sqrtT(sqT(x) + sqT(y));
    const T qy = z;
    const float rr = valT(qy) < 0.0 ? r1 : r2;
    const T cax = qx - minT(qx, cT(rr));
    const T cay = absT(qy) - cT(h);
    const T t = clamp01T(((cT(r2) - qx) * k2x + (cT(h) - qy) * k2y) * invK2);
    const T cbx = qx - cT(r2) + t * k2x;
    const T cby = qy - cT(h) + t * k2y;
    const float s = (valT(cbx) < 0.0 && valT(cay) < 0.0) ? -1.0 : 1.0;
    return sqrtT(minT(sqT(cax) + sqT(cay), sqT(cbx) + sqT(cby))) * s;
}

// sdf::polygon2d over the `count` points (x, y floats) from word `first`;
// without a revolve's edges on the axis when axisEdges is false.
T polygonT(uint t, uint first, uint count, T x, T y, bool axisEdges)
{
    T d = axisEdges ? sqT(x - cT(tapeFloat(t, first))) + sqT(y - cT(tapeFloat(t, first + 1u))) : cT(kTapeFloatMax);
    bool inside = false;
    for (uint i = 0u, j = count - 1u; i < count; j = i++) {
        const float vix = tapeFloat(t, first + 2u * i), viy = tapeFloat(t, first + 2u * i + 1u);
        const float vjx = tapeFloat(t, first + 2u * j), vjy = tapeFloat(t, first + 2u * j + 1u);
        if (!axisEdges && vix == 0.0 && vjx == 0.0) continue;
        const float ex = vjx - vix, ey = vjy - viy;
        const T wx = x - cT(vix), wy = y - cT(viy);
        const T s = clamp01T((wx * ex + wy * ey) / (ex * ex + ey * ey));
        d = minT(d, sqT(wx - s * ex) + sqT(wy - s * ey));
        const bool c1 = valT(y) >= viy, c2 = valT(y) < vjy, c3 = ex * valT(wy) > ey * valT(wx);
        if ((c1 && c2 && c3) || (!c1 && !c2 && !c3)) inside = !inside;
    }
    const T dist = sqrtT(d);
    return inside ? -dist : dist;
}

T extrusionT(T d2, T z, float halfHeight)
{
    const T wz = absT(z) - cT(halfHeight);
    return minT(maxT(d2, wz), cT(0.0)) + sqrtT(sqT(maxT(d2, cT(0.0))) + sqT(maxT(wz, cT(0.0))));
}

// sdf::revolution: the profile's [r, z] points at (length(x, y), z).
T revolutionT(uint t, uint first, uint count, T x, T y, T z)
{
    return polygonT(t, first, count, sqrtT(sqT(x) + sqT(y)), z, false);
}

// The shape at word s, at local point (x, y, z). NaN for a kind not named here.
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

// The stack lives in eight registers, top first (TileTape.cpp's st[j] is
// s<j>): a push shifts it down, a binary operation up. A dynamically indexed
// array would live in local memory (lavapipe slowed the whole kernel
// fourfold for one).
#if KERF_TAPE_MAX_STACK != 8
#error "the tape evaluator keeps exactly eight stack registers"
#endif

T KERF_TAPE_EVALUATE(uint t, vec3 p, out uint feature)
{
    const uint count = tapeWord(t, 0u);
    const uint shapes = KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * count;
    T s0 = cT(0.0), s1 = cT(0.0), s2 = cT(0.0), s3 = cT(0.0), s4 = cT(0.0), s5 = cT(0.0), s6 = cT(0.0), s7 = cT(0.0);
#ifdef KERF_TAPE_FEATURES
    uint f0 = 0u, f1 = 0u, f2 = 0u, f3 = 0u, f4 = 0u, f5 = 0u, f6 = 0u, f7 = 0u;
#endif
    tapeUnknownKind = false;
    for (uint i = 0u; i < count; ++i) {
        const uint code = tapeWord(t, KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * i);
        const float k = tapeFloat(t, KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * i + 1u);
        const uint op = code & 0xFFu;
        if (op == KERF_TAPE_PRIMITIVE) {
            const uint s = shapes + (code >> 8) * KERF_TAPE_SHAPE_WORDS;
            T x, y, z;
            localT(t, s + KERF_TAPE_SHAPE_FRAME, p, x, y, z);
            s7 = s6; s6 = s5; s5 = s4; s4 = s3; s3 = s2; s2 = s1; s1 = s0;
            s0 = shapeT(t, s, x, y, z);
#ifdef KERF_TAPE_FEATURES
            f7 = f6; f6 = f5; f5 = f4; f4 = f3; f3 = f2; f2 = f1; f1 = f0;
            f0 = tapeWord(t, s + 1u);
#endif
        } else if (op <= KERF_TAPE_SMOOTH_MAX) {
            const T b = s0, a = s1;
            T r;
            if (op == KERF_TAPE_MIN) {
                r = minT(a, b);
            } else if (op == KERF_TAPE_MAX) {
                r = maxT(a, b);
            } else {
                // The spec's polynomial smooth minimum, or its mirror (combine::smoothMin, smoothMax).
                const T h = maxT(cT(k) - absT(a - b), cT(0.0)) * (1.0 / k);
                r = op == KERF_TAPE_SMOOTH_MIN ? minT(a, b) - sqT(h) * (k * 0.25) : maxT(a, b) + sqT(h) * (k * 0.25);
            }
            s0 = r;
            s1 = s2; s2 = s3; s3 = s4; s4 = s5; s5 = s6; s6 = s7;
#ifdef KERF_TAPE_FEATURES
            // The deciding feature: the operand the exact min/max would pick.
            const bool isMin = op == KERF_TAPE_MIN || op == KERF_TAPE_SMOOTH_MIN;
            f0 = (isMin ? valT(b) < valT(a) : valT(a) < valT(b)) ? f0 : f1;
            f1 = f2; f2 = f3; f3 = f4; f4 = f5; f5 = f6; f6 = f7;
#endif
        } else if (op == KERF_TAPE_NEGATE) {
            s0 = -s0;
        } else if (op == KERF_TAPE_OFFSET) {
            s0 = s0 - cT(k);
        } else {
            s0 = maxT(s0, -(s0 + cT(k))); // shell
        }
    }
#ifdef KERF_TAPE_FEATURES
    feature = f0;
#else
    feature = 0u;
#endif
    // A min or max could pass over the NaN of an unknown kind: the whole result is NaN instead.
    return tapeUnknownKind ? cT(kTapeNaN) : s0;
}
