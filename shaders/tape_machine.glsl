// The stack machine of tape.glsl, written once for T (float values, vec4
// duals, vec2 intervals): a tile's encoded tape in post-order, primitives
// pushed, operations combining the top of the stack. Included only by
// tape.glsl after tape_shapes.glsl, which defines primitiveT, smoothMinT,
// smoothMaxT and shellT for T (tape.glsl itself for intervals), and
// KERF_TAPE_EVALUATE (this function's name); KERF_TAPE_FEATURES where the
// deciding feature is tracked.

// The stack lives in eight registers, top first (TileTape.cpp's st[j] is
// s<j>): a push shifts it down, a binary operation up. A dynamically indexed
// array would live in local memory (lavapipe slowed the whole kernel
// fourfold for one).
#if KERF_TAPE_MAX_STACK != 8
#error "the tape evaluator keeps exactly eight stack registers"
#endif

T KERF_TAPE_EVALUATE(uint t, T px, T py, T pz, out uint feature)
{
    const uint count = tapeWord(t, 0u);
    const uint shapes = KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * count;
    T s0 = cT(0.0), s1 = cT(0.0), s2 = cT(0.0), s3 = cT(0.0), s4 = cT(0.0), s5 = cT(0.0), s6 = cT(0.0), s7 = cT(0.0);
#ifdef KERF_TAPE_FEATURES
    uint f0 = 0u, f1 = 0u, f2 = 0u, f3 = 0u, f4 = 0u, f5 = 0u, f6 = 0u, f7 = 0u;
#endif
    tapeUnknownKind = false;
#ifdef KERF_TAPE_RECORD_PRUNING
    // Where each stack entry's subexpression starts (its first instruction),
    // top first like the stack: a binary operation whose one operand decides
    // it over the whole box leaves the other operand's instructions out.
    const bool recording = tapePruning && count <= 64u;
    uint r0 = 0u, r1 = 0u, r2 = 0u, r3 = 0u, r4 = 0u, r5 = 0u, r6 = 0u, r7 = 0u;
#endif
    for (uint i = 0u; i < count; ++i) {
#ifdef KERF_TAPE_PRUNING
        // The same for the whole group (its node's mask: a recording
        // evaluation only adds instructions it has passed).
        if (tapeSkipped(i)) continue;
#endif
        const uint code = tapeWord(t, KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * i);
        const float k = tapeFloat(t, KERF_TAPE_HEADER_WORDS + KERF_TAPE_INSTRUCTION_WORDS * i + 1u);
        const uint op = code & 0xFFu;
        if (op == KERF_TAPE_PRIMITIVE) {
            const uint s = shapes + (code >> 8) * KERF_TAPE_SHAPE_WORDS;
            s7 = s6; s6 = s5; s5 = s4; s4 = s3; s3 = s2; s2 = s1; s1 = s0;
            s0 = primitiveT(t, s, px, py, pz);
#ifdef KERF_TAPE_RECORD_PRUNING
            r7 = r6; r6 = r5; r5 = r4; r4 = r3; r3 = r2; r2 = r1; r1 = r0; r0 = i;
#endif
#ifdef KERF_TAPE_FEATURES
            f7 = f6; f6 = f5; f5 = f4; f4 = f3; f3 = f2; f2 = f1; f1 = f0;
            f0 = tapeWord(t, s + 1u);
#endif
        } else if (op <= KERF_TAPE_SMOOTH_MAX) {
            const T b = s0, a = s1;
            T r;
            if (op == KERF_TAPE_MIN) r = minT(a, b);
            else if (op == KERF_TAPE_MAX) r = maxT(a, b);
            else if (op == KERF_TAPE_SMOOTH_MIN) r = smoothMinT(a, b, k);
            else r = smoothMaxT(a, b, k);
            s0 = r;
            s1 = s2; s2 = s3; s3 = s4; s4 = s5; s5 = s6; s6 = s7;
#ifdef KERF_TAPE_RECORD_PRUNING
            if (recording) {
                // b's subexpression is [r0, i - 1], a's [r1, r0 - 1].
                const uint keep = tapeDecidingOperand(op, a, b, k);
                if (keep == 1u) tapeSkipRange(r0, i); // b and the operation: a stays on top
                else if (keep == 2u) { tapeSkipRange(r1, r0 - 1u); tapeSkipRange(i, i); }
            }
            r0 = r1; r1 = r2; r2 = r3; r3 = r4; r4 = r5; r5 = r6; r6 = r7;
#endif
#ifdef KERF_TAPE_FEATURES
            // The deciding feature: the operand the exact min/max would pick.
            const bool isMin = op == KERF_TAPE_MIN || op == KERF_TAPE_SMOOTH_MIN;
            // Within the tie band the left operand keeps it (FeatureTie.h).
            f0 = (isMin ? valT(b) + float(KERF_FEATURE_TIE) < valT(a) : valT(a) + float(KERF_FEATURE_TIE) < valT(b)) ? f0
                                                                                                                 : f1;
            f1 = f2; f2 = f3; f3 = f4; f4 = f5; f5 = f6; f6 = f7;
#endif
        } else if (op == KERF_TAPE_NEGATE) {
            s0 = negT(s0);
        } else if (op == KERF_TAPE_OFFSET) {
            s0 = subT(s0, cT(k));
        } else {
            s0 = shellT(s0, k);
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
