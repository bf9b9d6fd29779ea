// The feature id the tracers write where a section plane cuts the solid (the
// cap), rather than a surface of the part: kNoFeature - 1. A preprocessor
// definition only, so that C++ (Section.hpp) and every shader that writes or
// shades a cap (trace.comp, brick.frag, part.frag through RenderShared.h)
// read the same value.
#ifndef KERF_SECTION_CAP_H
#define KERF_SECTION_CAP_H

#define KERF_SECTION_CAP_FEATURE 0xFFFFFFFEu

#endif
