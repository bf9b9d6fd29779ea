#pragma once
// Triangles by where they are, for "what could this new triangle cross?"
// while a mesh changes (the refiner's splits and flips, the collapser's
// collapses).
//
// A dynamic bounding-volume tree (as in Box2D's b2DynamicTree and Bullet's
// btDbvt): one leaf per triangle with its box, inner nodes with the union
// of their children's, kept balanced by AVL rotations as leaves come and
// go. A query visits O(log n + k) nodes whatever the triangles' sizes:
// simplification leaves triangles from a hundredth of a millimetre to a
// metre across, and a grid sized for one is slow for the other (a box the
// size of a large triangle covers thousands of a fine grid's cells).

#include <glm/glm.hpp>

#include <cstdint>
#include <utility>
#include <vector>

namespace kerf::mesher {

class TriangleTree {
public:
    /// Adds triangle t with the box [lo, hi]; t must not be in the tree.
    void insert(std::uint32_t t, const glm::dvec3& lo, const glm::dvec3& hi)
    {
        if (t >= leafOf_.size()) leafOf_.resize(std::size_t(t) + 1, kNull);
        const int leaf = allocate();
        Node& n = nodes_[std::size_t(leaf)];
        n.lo = lo;
        n.hi = hi;
        n.item = t;
        n.height = 0;
        leafOf_[t] = leaf;
        insertLeaf(leaf);
    }

    /// Removes triangle t (its box as inserted: the tree remembers it).
    void erase(std::uint32_t t, const glm::dvec3& = {}, const glm::dvec3& = {})
    {
        if (t >= leafOf_.size() || leafOf_[t] == kNull) return;
        const int leaf = leafOf_[t];
        leafOf_[t] = kNull;
        removeLeaf(leaf);
        release(leaf);
    }

    /// Calls visit(t) for every triangle whose box meets [lo, hi].
    template <class Visit> void query(const glm::dvec3& lo, const glm::dvec3& hi, Visit&& visit) const
    {
        if (root_ == kNull) return;
        // Depth-first: at most one pending sibling per level of a balanced
        // tree (AVL: height below 1.45 log2 of the leaves).
        int stack[kMaxDepth];
        int top = 0;
        stack[top++] = root_;
        while (top > 0) {
            const Node& n = nodes_[std::size_t(stack[--top])];
            if (glm::any(glm::lessThan(hi, n.lo)) || glm::any(glm::greaterThan(lo, n.hi))) continue;
            if (n.leaf()) {
                visit(n.item);
                continue;
            }
            stack[top++] = n.child1;
            stack[top++] = n.child2;
        }
    }

    /// Calls visit(t) for triangles whose box meets [lo, hi] until one
    /// returns true; returns whether one did.
    template <class Visit> bool queryAny(const glm::dvec3& lo, const glm::dvec3& hi, Visit&& visit) const
    {
        bool found = false;
        if (root_ == kNull) return found;
        int stack[kMaxDepth];
        int top = 0;
        stack[top++] = root_;
        while (top > 0 && !found) {
            const Node& n = nodes_[std::size_t(stack[--top])];
            if (glm::any(glm::lessThan(hi, n.lo)) || glm::any(glm::greaterThan(lo, n.hi))) continue;
            if (n.leaf()) {
                found = visit(n.item);
                continue;
            }
            stack[top++] = n.child1;
            stack[top++] = n.child2;
        }
        return found;
    }

private:
    static constexpr int kNull = -1;
    static constexpr int kMaxDepth = 256;

    struct Node {
        glm::dvec3 lo{0.0}, hi{0.0};
        int parent = kNull;
        int child1 = kNull, child2 = kNull; // child1 is also the free list's link
        int height = -1;                    // 0 for a leaf, -1 when free
        std::uint32_t item = 0;
        bool leaf() const { return child1 == kNull; }
    };

    // Half the surface of a box: the cost of a node in the insertion
    // heuristic (the chance that a query box meets it). Flat boxes (faces
    // along an axis) still have one.
    static double cost(const glm::dvec3& lo, const glm::dvec3& hi)
    {
        const glm::dvec3 d = hi - lo;
        return d.x * d.y + d.y * d.z + d.z * d.x;
    }

    int allocate()
    {
        if (free_ == kNull) {
            nodes_.emplace_back();
            return int(nodes_.size() - 1);
        }
        const int n = free_;
        free_ = nodes_[std::size_t(n)].child1;
        nodes_[std::size_t(n)] = Node{};
        return n;
    }

    void release(int n)
    {
        nodes_[std::size_t(n)].child1 = free_;
        nodes_[std::size_t(n)].height = -1;
        free_ = n;
    }

    Node& at(int i) { return nodes_[std::size_t(i)]; }

    void insertLeaf(int leaf)
    {
        if (root_ == kNull) {
            root_ = leaf;
            at(leaf).parent = kNull;
            return;
        }
        // The sibling that makes the tree grow least (Box2D's descent).
        const glm::dvec3 lo = at(leaf).lo, hi = at(leaf).hi;
        int index = root_;
        while (!at(index).leaf()) {
            const Node& n = at(index);
            const double area = cost(n.lo, n.hi);
            const double combined = cost(glm::min(n.lo, lo), glm::max(n.hi, hi));
            const double here = 2.0 * combined;             // a new parent of this node and the leaf
            const double inherited = 2.0 * (combined - area); // what every deeper choice adds above
            auto descend = [&](int c) {
                const Node& ch = at(c);
                const double grown = cost(glm::min(ch.lo, lo), glm::max(ch.hi, hi));
                return ch.leaf() ? grown + inherited : grown - cost(ch.lo, ch.hi) + inherited;
            };
            const double cost1 = descend(n.child1), cost2 = descend(n.child2);
            if (here < cost1 && here < cost2) break;
            index = cost1 < cost2 ? n.child1 : n.child2;
        }
        const int sibling = index;
        const int oldParent = at(sibling).parent;
        const int parent = allocate();
        at(parent).parent = oldParent;
        at(parent).lo = glm::min(lo, at(sibling).lo);
        at(parent).hi = glm::max(hi, at(sibling).hi);
        at(parent).height = at(sibling).height + 1;
        at(parent).child1 = sibling;
        at(parent).child2 = leaf;
        at(sibling).parent = parent;
        at(leaf).parent = parent;
        if (oldParent == kNull) {
            root_ = parent;
        } else if (at(oldParent).child1 == sibling) {
            at(oldParent).child1 = parent;
        } else {
            at(oldParent).child2 = parent;
        }
        refit(at(leaf).parent);
    }

    void removeLeaf(int leaf)
    {
        if (leaf == root_) {
            root_ = kNull;
            return;
        }
        const int parent = at(leaf).parent;
        const int grandParent = at(parent).parent;
        const int sibling = at(parent).child1 == leaf ? at(parent).child2 : at(parent).child1;
        if (grandParent == kNull) {
            root_ = sibling;
            at(sibling).parent = kNull;
            release(parent);
            return;
        }
        if (at(grandParent).child1 == parent) at(grandParent).child1 = sibling;
        else at(grandParent).child2 = sibling;
        at(sibling).parent = grandParent;
        release(parent);
        refit(grandParent);
    }

    // From `index` up to the root: balance, then the box and the height.
    void refit(int index)
    {
        while (index != kNull) {
            index = balance(index);
            Node& n = at(index);
            const Node& c1 = at(n.child1);
            const Node& c2 = at(n.child2);
            n.height = 1 + std::max(c1.height, c2.height);
            n.lo = glm::min(c1.lo, c2.lo);
            n.hi = glm::max(c1.hi, c2.hi);
            index = n.parent;
        }
    }

    // A rotation where one child of `a` is two levels taller than the other
    // (b2DynamicTree::Balance); returns the node now where `a` was.
    int balance(int a)
    {
        if (at(a).leaf() || at(a).height < 2) return a;
        const int b = at(a).child1, c = at(a).child2;
        const int diff = at(c).height - at(b).height;
        if (diff > 1) return rotateUp(a, c);
        if (diff < -1) return rotateUp(a, b);
        return a;
    }

    // `up`, the taller child of `a`, takes a's place; a keeps its other
    // child and the shorter of up's children.
    int rotateUp(int a, int up)
    {
        const int f = at(up).child1, g = at(up).child2;
        at(up).child1 = a;
        at(up).parent = at(a).parent;
        at(a).parent = up;
        if (at(up).parent == kNull) root_ = up;
        else if (at(at(up).parent).child1 == a) at(at(up).parent).child1 = up;
        else at(at(up).parent).child2 = up;
        const bool keepF = at(f).height > at(g).height;
        const int stays = keepF ? f : g, moves = keepF ? g : f;
        at(up).child2 = stays;
        if (at(a).child1 == up) at(a).child1 = moves;
        else at(a).child2 = moves;
        at(moves).parent = a;
        Node& na = at(a);
        na.lo = glm::min(at(na.child1).lo, at(na.child2).lo);
        na.hi = glm::max(at(na.child1).hi, at(na.child2).hi);
        na.height = 1 + std::max(at(na.child1).height, at(na.child2).height);
        Node& nu = at(up);
        nu.lo = glm::min(at(nu.child1).lo, at(nu.child2).lo);
        nu.hi = glm::max(at(nu.child1).hi, at(nu.child2).hi);
        nu.height = 1 + std::max(at(nu.child1).height, at(nu.child2).height);
        return up;
    }

    std::vector<Node> nodes_;
    std::vector<int> leafOf_; // triangle -> its leaf
    int root_ = kNull;
    int free_ = kNull;
};

} // namespace kerf::mesher
