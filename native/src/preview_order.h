// Which output points a live-drag preview step visits, and in what order, without a pass over
// every point of the scene: a step relights a fixed amount of work nearest the dragged object,
// and in a room of a million points any per-point pass would cost more than that work.
// Private to the preview's sources (preview.cpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "final_gather_trace.h"

namespace radiosity {

// Whether a shadow ray of some lamp from x (normal n) may meet one of `clips`: a point or spot
// light's segment hull; the sun's rays toward the sun disk; the sky's, anywhere in front
// (unless `sky` is false: lamps whose shadows are sharp and may fall far from the boxes).
bool lamps_meet(const SceneDesc& scene, const Hierarchy& h, const Vec3& x, const Vec3& n, const std::vector<Aabb>& clips,
                bool sky = true);

// Where a trace's points are: binned into the cells of a grid (a cell's points in index
// order, its box tight around them), each object's points, each point's corners. Made at the
// first preview after a trace; the points do not move while it lives.
class PointIndex {
public:
    PointIndex(const std::vector<fg::Point>& points, const std::vector<std::vector<int>>& corner_point);
    struct Cell {
        Aabb box;
        uint32_t begin = 0, end = 0;  // its points: points()[begin, end)
    };
    const std::vector<Cell>& cells() const { return cells_; }
    const uint32_t* points() const { return cell_points_.data(); }
    // Object o's points in index order: [first, last).
    std::pair<const uint32_t*, const uint32_t*> object_points(size_t o) const;
    // Point i's corners, (object, corner) in increasing order: [first, last).
    std::pair<const std::pair<int, int>*, const std::pair<int, int>*> corners(size_t i) const;

private:
    std::vector<Cell> cells_;
    std::vector<uint32_t> cell_points_;
    std::vector<uint32_t> object_first_, object_points_;
    std::vector<uint32_t> corner_first_;
    std::vector<std::pair<int, int>> corners_;
};

// One step's order: the points inside an old or new box and those an earlier step showed
// unlit (a footprint: its light must come back as soon as the object leaves; relit at every
// step whatever the work), the dragged objects' own points (from `turn` on, so that steps that
// stop early take turns among them), and the others: first those a point, spot or sun light's
// shadow rays may carry a box's sharp shadow to (a low sun throws it across the room), then
// the rest (the sky's soft shadow), each by distance to the nearest box in rings of a 64th of
// the scene, within a ring by index. The others are found cell by cell as they are asked for,
// nearest cells first. Points of no object are left out.
class PreviewOrder {
public:
    // `unlit`: per point, an earlier step showed it unlit; `unlit_points`: those points (and
    // perhaps some no longer unlit). `threads`: parallel_for's, for the cells' and points' keys.
    PreviewOrder(const FinalGather::Solution& s, const std::vector<fg::Point>& points, const PointIndex& index,
                 const FinalGather::Preview& p, const std::vector<char>& unlit,
                 const std::vector<uint32_t>& unlit_points, size_t turn, int threads);
    const std::vector<uint32_t>& inside() const { return inside_; }
    const std::vector<uint32_t>& dragged() const { return dragged_; }
    // Appends up to n more of the others, nearest first, to `out`; false when none are left.
    bool next(size_t n, std::vector<uint32_t>& out);
    // The others not yet handed out.
    size_t others_left() const { return others_ - handed_; }

private:
    static constexpr int kRings = 64;
    static constexpr int kKeys = 2 * kRings + 2;  // 0 inside, 1 dragged, then sharp and soft rings
    bool counted(uint32_t i) const;  // a point of an object the scene has, not dragged
    int key_of(uint32_t i) const;
    void open(int key);  // bins every cell that may hold a point of `key`, sorts the key's points
    const FinalGather::Solution& s_;
    const std::vector<fg::Point>& points_;
    const PointIndex& index_;
    const FinalGather::Preview& p_;
    const std::vector<char>& unlit_;
    int threads_;
    double step_;
    std::vector<uint32_t> inside_, dragged_;
    std::vector<uint32_t> cells_by_key_;  // cells, by the least key a point of theirs may have
    std::vector<int> cell_key_;
    size_t cells_binned_ = 0;
    std::vector<std::vector<uint32_t>> bins_;  // per key, the points binned so far
    int key_ = 2;                              // the key being handed out
    size_t at_ = 0;                            // ... from bins_[key_][at_]
    bool opened_ = false;
    size_t others_ = 0, handed_ = 0;
};

}  // namespace radiosity
