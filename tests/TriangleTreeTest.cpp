// The mesher's dynamic box tree (mesher/src/TriangleTree.hpp) against brute
// force: after any mix of insertions and removals, a query reports exactly
// the triangles whose boxes meet the query box, each once.
#include "TriangleTree.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace kerf::mesher {
namespace {

struct Box {
    glm::dvec3 lo, hi;
};

bool meets(const Box& a, const Box& b)
{
    return !glm::any(glm::lessThan(a.hi, b.lo)) && !glm::any(glm::greaterThan(a.lo, b.hi));
}

TEST(TriangleTree, QueriesMatchBruteForceThroughInsertionsAndRemovals)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> where(-500.0, 500.0);
    // Sizes from a hundredth of a millimetre to a metre, and flat boxes.
    std::uniform_real_distribution<double> exponent(-2.0, 3.0);
    auto randomBox = [&] {
        const glm::dvec3 c(where(rng), where(rng), where(rng));
        glm::dvec3 half(std::pow(10.0, exponent(rng)), std::pow(10.0, exponent(rng)), std::pow(10.0, exponent(rng)));
        if (rng() % 4 == 0) half[rng() % 3] = 0.0;
        return Box{c - half, c + half};
    };
    TriangleTree tree;
    std::vector<Box> boxes;
    std::vector<bool> present;
    for (int step = 0; step < 20000; ++step) {
        const unsigned action = rng() % 10;
        if (action < 6 || boxes.empty()) {
            const std::uint32_t t = std::uint32_t(boxes.size());
            boxes.push_back(randomBox());
            present.push_back(true);
            tree.insert(t, boxes[t].lo, boxes[t].hi);
        } else if (action < 9) {
            const std::uint32_t t = std::uint32_t(rng() % boxes.size());
            if (present[t]) {
                tree.erase(t);
                present[t] = false;
            } else {
                boxes[t] = randomBox(); // back, somewhere else
                tree.insert(t, boxes[t].lo, boxes[t].hi);
                present[t] = true;
            }
        } else {
            const Box q = randomBox();
            std::vector<std::uint32_t> got, expected;
            tree.query(q.lo, q.hi, [&](std::uint32_t t) { got.push_back(t); });
            for (std::uint32_t t = 0; t < boxes.size(); ++t)
                if (present[t] && meets(boxes[t], q)) expected.push_back(t);
            std::sort(got.begin(), got.end());
            ASSERT_EQ(got, expected) << "at step " << step;
        }
    }
}

TEST(TriangleTree, EmptiedAndRefilled)
{
    TriangleTree tree;
    for (std::uint32_t t = 0; t < 1000; ++t)
        tree.insert(t, glm::dvec3(double(t)), glm::dvec3(double(t) + 0.5));
    for (std::uint32_t t = 0; t < 1000; ++t)
        tree.erase(t);
    int visits = 0;
    tree.query(glm::dvec3(-1e9), glm::dvec3(1e9), [&](std::uint32_t) { ++visits; });
    EXPECT_EQ(visits, 0);
    // A sorted run of insertions (the worst case of an unbalanced tree)
    // still answers exactly.
    for (std::uint32_t t = 0; t < 100000; ++t)
        tree.insert(t, glm::dvec3(double(t), 0.0, 0.0), glm::dvec3(double(t) + 0.25, 1.0, 0.0));
    std::vector<std::uint32_t> got;
    tree.query(glm::dvec3(5000.1, 0.5, 0.0), glm::dvec3(5001.1, 0.5, 0.0), [&](std::uint32_t t) { got.push_back(t); });
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, (std::vector<std::uint32_t>{5000, 5001}));
}

} // namespace
} // namespace kerf::mesher
