#pragma once
// Garland and Heckbert's error quadric: the weighted sum of squared
// distances from a point to a set of planes, as a symmetric 4x4 form
// Q(p) = p^T A p + 2 b^T p + c. The planes here are tangent planes of the
// exact surface at mesh vertices (position and exact normal: Hermite data),
// so a quadric remembers the surface a simplified vertex stands for, sharp
// creases included (the planes of both sides).
//
// Coordinates should be small (relative to a nearby origin): Q(p) cancels
// terms of size |p|^2 and loses their precision.

#include "SymmetricEigen.hpp"

#include <glm/glm.hpp>

namespace kerf::mesher {

struct Quadric {
    double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0; // A
    double b0 = 0, b1 = 0, b2 = 0;                                // b
    double c = 0;
    double weight = 0; // total weight of the planes (mm^2 of surface)

    /// The plane through p with unit normal n, weighted by w.
    static Quadric plane(const glm::dvec3& n, const glm::dvec3& p, double w)
    {
        const double d = -glm::dot(n, p);
        Quadric q;
        q.a00 = w * n.x * n.x;
        q.a01 = w * n.x * n.y;
        q.a02 = w * n.x * n.z;
        q.a11 = w * n.y * n.y;
        q.a12 = w * n.y * n.z;
        q.a22 = w * n.z * n.z;
        q.b0 = w * n.x * d;
        q.b1 = w * n.y * d;
        q.b2 = w * n.z * d;
        q.c = w * d * d;
        q.weight = w;
        return q;
    }

    Quadric& operator+=(const Quadric& o)
    {
        a00 += o.a00;
        a01 += o.a01;
        a02 += o.a02;
        a11 += o.a11;
        a12 += o.a12;
        a22 += o.a22;
        b0 += o.b0;
        b1 += o.b1;
        b2 += o.b2;
        c += o.c;
        weight += o.weight;
        return *this;
    }

    /// Weighted sum of squared distances from p to the planes.
    double sum(const glm::dvec3& p) const
    {
        const double x = p.x, y = p.y, z = p.z;
        const double v = x * (a00 * x + 2.0 * (a01 * y + a02 * z + b0)) + y * (a11 * y + 2.0 * (a12 * z + b1)) +
                         z * (a22 * z + 2.0 * b2) + c;
        return v > 0.0 ? v : 0.0; // rounding can dip below 0
    }
    /// Mean squared distance (mm^2); 0 for an empty quadric.
    double mean(const glm::dvec3& p) const { return weight > 0.0 ? sum(p) / weight : 0.0; }

    /// The point nearest `around` where the planes meet best: on a sharp
    /// edge for planes of two sides, at a corner for three; directions the
    /// planes hardly constrain (eigenvalues below a hundredth of the
    /// largest) stay at `around`. `rank` receives the number of directions
    /// that were constrained.
    glm::dvec3 minimizer(const glm::dvec3& around, int* rank = nullptr) const
    {
        const double A[3][3] = {{a00, a01, a02}, {a01, a11, a12}, {a02, a12, a22}};
        return truncatedSolve(A, glm::dvec3(-b0, -b1, -b2), around, 1e-2, rank);
    }
};

} // namespace kerf::mesher
