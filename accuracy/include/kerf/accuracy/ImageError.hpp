#pragma once
// How far a traced picture lies from a reference picture of the same camera
// (in `kerf bench`: the voxel trace against the exact sphere trace).
//
// Depth error: |depth - reference depth| in mm along the pixel's ray, on the
// pixels both images hit. Normal error: the angle between the two unit
// normals in degrees, on the same pixels (computed with atan2 of the cross
// and dot products, which stays accurate for tiny angles where acos does
// not). Pixels where only one image hits something are counted apart: a
// silhouette off by a pixel is not a depth error of the whole ray length.

#include "kerf/accuracy/ErrorStats.hpp"
#include "kerf/tracer/Image.hpp"

#include <cstddef>

namespace kerf {

struct ImageError {
    std::size_t pixels = 0;
    std::size_t bothHit = 0;
    std::size_t onlyImage = 0;     // hit in the measured image only
    std::size_t onlyReference = 0; // hit in the reference only
    ErrorStats depthMm;            // over bothHit pixels
    ErrorStats normalDegrees;      // over bothHit pixels

    /// Pixels where exactly one image hits, as a fraction of the pixels
    /// either image hits (0 when neither hits anything).
    double mismatchFraction() const
    {
        const std::size_t either = bothHit + onlyImage + onlyReference;
        return either ? double(onlyImage + onlyReference) / double(either) : 0.0;
    }
};

/// Compares `image` with `reference` pixel by pixel. Throws
/// std::invalid_argument when their sizes differ.
ImageError compareImages(const TraceImage& image, const TraceImage& reference);

} // namespace kerf
