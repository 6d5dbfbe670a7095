// Which points a preview step visits, nearest the dragged object first (preview_order.h).
#include "preview_order.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "radiosity/parallel.h"
#include "radiosity/transfer.h"

namespace radiosity {

namespace {

// Whether some clip's bounding sphere comes within `spread` (plus the distance along it times
// `slope`) of the segment from x along unit u for length len: a quick, conservative test.
bool near_axis(const std::vector<Aabb>& clips, const Vec3& x, const Vec3& u, double len, double spread, double slope) {
    for (const Aabb& c : clips) {
        const Vec3 o = c.center() - x;
        const double R = 0.5 * length(c.hi - c.lo) + 1e-4;
        const double t = std::clamp(dot(o, u), 0.0, len);
        if (length(o - u * t) <= R + spread + t * slope) return true;
    }
    return false;
}

// The sun's shadow rays start at x and end past the scene's far end toward the sun, in a
// cone as wide as the disk.
struct SunShaft {
    double far, slope;
    Vec3 toward;
    SunShaft(const LightDesc& d, const Hierarchy& h)
        : far(4.0 * h.scene_diag), slope(std::tan(0.5 * std::min(d.angle, 3.0))), toward(normalize(d.direction) * -1.0) {}
};

// Whether a point, spot or sun light's shadow ray from some point within `radius` of c may
// meet one of `clips` (lamps_meet's first test, widened by the radius: a segment from a point
// within `radius` of c lies within `radius` of the segment from c).
bool sharp_lamps_may_meet(const SceneDesc& scene, const Hierarchy& h, const Vec3& c, double radius,
                          const std::vector<Aabb>& clips) {
    for (const LightDesc& d : scene.lights()) {
        if (!(d.intensity.max() > 0)) continue;
        if (d.type == LightDesc::Type::Point || d.type == LightDesc::Type::Spot) {
            const Vec3 q = h.to_internal(d.position);
            const double r = d.radius / h.unit;
            const double len = length(q - c);
            if (len <= radius || near_axis(clips, c, (q - c) / len, len, r + radius, 0.0)) return true;
        } else if (d.type == LightDesc::Type::Sun) {
            const SunShaft sun(d, h);
            if (near_axis(clips, c, sun.toward, sun.far, 1e-9 + radius, sun.slope)) return true;
        }
    }
    return false;
}

// Distance from x to the nearest of `boxes` (0 inside one).
double distance_to(const std::vector<Aabb>& boxes, const Vec3& x) {
    double d2 = std::numeric_limits<double>::max();
    for (const Aabb& b : boxes) {
        const Vec3 q = vmax(b.lo, vmin(x, b.hi));
        d2 = std::min(d2, dot(x - q, x - q));
    }
    return std::sqrt(d2);
}

// Distance from box a to the nearest of `boxes`.
double distance_to(const std::vector<Aabb>& boxes, const Aabb& a) {
    double d2 = std::numeric_limits<double>::max();
    for (const Aabb& b : boxes) d2 = std::min(d2, a.distance2(b));
    return std::sqrt(d2);
}

}  // namespace

bool lamps_meet(const SceneDesc& scene, const Hierarchy& h, const Vec3& x, const Vec3& n, const std::vector<Aabb>& clips,
                bool sky) {
    for (const LightDesc& d : scene.lights()) {
        if (!(d.intensity.max() > 0)) continue;
        if (!sky && d.type == LightDesc::Type::Sky) continue;
        Aabb lb;
        if (d.type == LightDesc::Type::Point || d.type == LightDesc::Type::Spot) {
            const Vec3 q = h.to_internal(d.position);
            const double r = d.radius / h.unit;
            const double len = length(q - x);
            if (len > 0 && !near_axis(clips, x, (q - x) / len, len, r, 0.0)) continue;
            lb = Aabb::around(q, r);
        } else if (d.type == LightDesc::Type::Sun) {
            const SunShaft sun(d, h);
            if (!near_axis(clips, x, sun.toward, sun.far, 1e-9, sun.slope)) continue;
            const Vec3 q = x - d.direction * sun.far;
            const double r = sun.far * sun.slope + 1e-9;
            lb = Aabb::around(q, r);
        } else {
            for (const Aabb& c : clips)
                for (int k = 0; k < 8; ++k) {
                    const Vec3 corner{(k & 1) ? c.hi.x : c.lo.x, (k & 2) ? c.hi.y : c.lo.y, (k & 4) ? c.hi.z : c.lo.z};
                    if (dot(corner - x, n) > 0) return true;
                }
            continue;
        }
        if (hull_meets(x, lb, clips)) return true;
    }
    return false;
}

PointIndex::PointIndex(const std::vector<fg::Point>& points, const std::vector<std::vector<int>>& corner_point) {
    // A grid of about 32 points a cell over the points' box (no axis over 256 cells).
    Aabb all;
    for (const fg::Point& pt : points) all.grow(pt.x);
    const size_t n = points.size();
    int dims[3] = {1, 1, 1};
    if (n > 0) {
        const Vec3 e = all.extent();
        const double biggest = std::max({e.x, e.y, e.z});
        if (biggest > 0) {
            double volume = 1;
            for (int k = 0; k < 3; ++k) volume *= std::max(e[k], biggest * 1e-3);
            const double side = std::cbrt(volume / std::max(1.0, double(n) / 32.0));
            for (int k = 0; k < 3; ++k) dims[k] = std::clamp(int(std::ceil(e[k] / side)), 1, 256);
        }
    }
    auto cell_of = [&](const Vec3& x) {
        size_t id = 0;
        for (int k = 0; k < 3; ++k) {
            const double e = all.hi[k] - all.lo[k];
            const int c = e > 0 ? std::clamp(int((x[k] - all.lo[k]) / e * dims[k]), 0, dims[k] - 1) : 0;
            id = id * size_t(dims[k]) + size_t(c);
        }
        return id;
    };
    const size_t grid = size_t(dims[0]) * size_t(dims[1]) * size_t(dims[2]);
    std::vector<uint32_t> first(grid + 1, 0);
    std::vector<size_t> id(n);
    for (size_t i = 0; i < n; ++i) ++first[(id[i] = cell_of(points[i].x)) + 1];
    for (size_t c = 0; c < grid; ++c) first[c + 1] += first[c];
    cell_points_.resize(n);
    {
        std::vector<uint32_t> at(first.begin(), first.end() - 1);
        for (size_t i = 0; i < n; ++i) cell_points_[at[id[i]]++] = uint32_t(i);
    }
    for (size_t c = 0; c < grid; ++c) {
        if (first[c] == first[c + 1]) continue;
        Cell cell;
        cell.begin = first[c];
        cell.end = first[c + 1];
        for (uint32_t k = cell.begin; k < cell.end; ++k) cell.box.grow(points[cell_points_[k]].x);
        cells_.push_back(cell);
    }
    // Each object's points.
    size_t objects = corner_point.size();
    for (const fg::Point& pt : points) objects = std::max(objects, size_t(std::max(pt.object, -1) + 1));
    object_first_.assign(objects + 1, 0);
    for (const fg::Point& pt : points)
        if (pt.object >= 0) ++object_first_[size_t(pt.object) + 1];
    for (size_t o = 0; o < objects; ++o) object_first_[o + 1] += object_first_[o];
    object_points_.resize(object_first_[objects]);
    {
        std::vector<uint32_t> at(object_first_.begin(), object_first_.end() - 1);
        for (size_t i = 0; i < n; ++i)
            if (points[i].object >= 0) object_points_[at[size_t(points[i].object)]++] = uint32_t(i);
    }
    // Each point's corners.
    corner_first_.assign(n + 1, 0);
    for (const std::vector<int>& cp : corner_point)
        for (int p : cp)
            if (p >= 0) ++corner_first_[size_t(p) + 1];
    for (size_t i = 0; i < n; ++i) corner_first_[i + 1] += corner_first_[i];
    corners_.resize(corner_first_[n]);
    std::vector<uint32_t> at(corner_first_.begin(), corner_first_.end() - 1);
    for (size_t o = 0; o < corner_point.size(); ++o)
        for (size_t c = 0; c < corner_point[o].size(); ++c)
            if (const int p = corner_point[o][c]; p >= 0) corners_[at[size_t(p)]++] = {int(o), int(c)};
}

std::pair<const uint32_t*, const uint32_t*> PointIndex::object_points(size_t o) const {
    if (o + 1 >= object_first_.size()) return {nullptr, nullptr};
    return {object_points_.data() + object_first_[o], object_points_.data() + object_first_[o + 1]};
}

std::pair<const std::pair<int, int>*, const std::pair<int, int>*> PointIndex::corners(size_t i) const {
    return {corners_.data() + corner_first_[i], corners_.data() + corner_first_[i + 1]};
}

PreviewOrder::PreviewOrder(const FinalGather::Solution& s, const std::vector<fg::Point>& points,
                           const PointIndex& index, const FinalGather::Preview& p, const std::vector<char>& unlit,
                           const std::vector<uint32_t>& unlit_points, size_t turn, int threads)
    : s_(s), points_(points), index_(index), p_(p), unlit_(unlit), threads_(threads), step_(s.h.scene_diag / kRings),
      bins_(kKeys) {
    const size_t no = p.moved.size();
    size_t valid = 0;
    for (size_t o = 0; o < no; ++o) {
        const auto [first, last] = index.object_points(o);
        valid += size_t(last - first);
        if (p.moved[o]) dragged_.insert(dragged_.end(), first, last);
    }
    std::sort(dragged_.begin(), dragged_.end());
    if (!dragged_.empty())
        std::rotate(dragged_.begin(), dragged_.begin() + long(turn % dragged_.size()), dragged_.end());
    // The first run: those shown unlit, then those inside a box (in the cells the boxes meet).
    for (uint32_t i : unlit_points)
        if (unlit[i] && counted(i)) inside_.push_back(i);
    const auto& cells = index.cells();
    cell_key_.resize(cells.size());
    std::vector<char> meets(cells.size(), 0);
    parallel_for(cells.size(), threads, [&](size_t c) {
        const PointIndex::Cell& cell = cells[c];
        const double d = distance_to(p.clips, cell.box);
        meets[c] = d == 0;
        // The least key a point of the cell may have (a hair less than the points' own
        // distances, whose rounding may differ).
        const int ring = int(std::min(double(kRings - 1), d * (1 - 1e-9) / step_));
        const bool sharp = sharp_lamps_may_meet(s.scene, s.h, cell.box.center(), 0.5 * cell.box.diagonal(), p.clips);
        cell_key_[c] = (sharp ? 2 : 2 + kRings) + ring;
    }, 256);
    for (size_t c = 0; c < cells.size(); ++c) {
        if (!meets[c]) continue;
        for (uint32_t k = cells[c].begin; k < cells[c].end; ++k) {
            const uint32_t i = index.points()[k];
            if (counted(i) && !unlit[i] && distance_to(p.clips, points[i].x) == 0) inside_.push_back(i);
        }
    }
    std::sort(inside_.begin(), inside_.end());
    inside_.erase(std::unique(inside_.begin(), inside_.end()), inside_.end());
    others_ = valid - dragged_.size() - inside_.size();
    // The cells by key, in index order within a key (a counting sort: keys are few).
    std::vector<uint32_t> first(kKeys + 1, 0);
    for (int k : cell_key_) ++first[size_t(k) + 1];
    for (int k = 0; k < kKeys; ++k) first[size_t(k) + 1] += first[size_t(k)];
    cells_by_key_.resize(cells.size());
    for (size_t c = 0; c < cells.size(); ++c) cells_by_key_[first[size_t(cell_key_[c])]++] = uint32_t(c);
}

bool PreviewOrder::counted(uint32_t i) const {
    const int o = points_[i].object;
    return o >= 0 && size_t(o) < p_.moved.size() && !p_.moved[size_t(o)];
}

int PreviewOrder::key_of(uint32_t i) const {
    const fg::Point& pt = points_[i];
    const int ring = int(std::min(double(kRings - 1), distance_to(p_.clips, pt.x) / step_));
    const bool sharp = !pt.covered && lamps_meet(s_.scene, s_.h, pt.x, pt.n, p_.clips, false);
    return (sharp ? 2 : 2 + kRings) + ring;
}

void PreviewOrder::open(int key) {
    // The points of the cells opened now, their keys found in parallel, binned in that order.
    const auto& cells = index_.cells();
    std::vector<uint32_t> pending;
    for (; cells_binned_ < cells_by_key_.size() && cell_key_[cells_by_key_[cells_binned_]] <= key; ++cells_binned_) {
        const PointIndex::Cell& cell = cells[cells_by_key_[cells_binned_]];
        pending.insert(pending.end(), index_.points() + cell.begin, index_.points() + cell.end);
    }
    std::vector<int> keys(pending.size());
    parallel_for(pending.size(), threads_, [&](size_t j) {
        const uint32_t i = pending[j];
        keys[j] = !counted(i) || unlit_[i] || distance_to(p_.clips, points_[i].x) == 0 ? -1 : key_of(i);  // (inside())
    }, 64);
    for (size_t j = 0; j < pending.size(); ++j)
        if (keys[j] >= 0) bins_[size_t(keys[j])].push_back(pending[j]);
    std::sort(bins_[size_t(key)].begin(), bins_[size_t(key)].end());
}

bool PreviewOrder::next(size_t n, std::vector<uint32_t>& out) {
    size_t added = 0;
    while (added < n && key_ < kKeys) {
        if (!opened_) {
            open(key_);
            opened_ = true;
        }
        const std::vector<uint32_t>& bin = bins_[size_t(key_)];
        const size_t take = std::min(n - added, bin.size() - at_);
        out.insert(out.end(), bin.begin() + long(at_), bin.begin() + long(at_ + take));
        at_ += take;
        added += take;
        if (at_ == bin.size()) {
            std::vector<uint32_t>().swap(bins_[size_t(key_)]);
            ++key_;
            at_ = 0;
            opened_ = false;
        }
    }
    handed_ += added;
    return added > 0;
}

}  // namespace radiosity
