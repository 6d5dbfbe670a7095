// The near field's direct-light term (near_field): the point's own plane near a
// sender a hair away is taken as the point's radiance there (the two sides of a contact are
// solved together), but its direct light is not the point's. A box's corner vertex in the
// box's shadow has the lamp's penumbra a tenth of a millimetre away on the floor in front of
// the same face, and the face's first millimetre sees it: read as the point's dark floor, the
// vertex would come out dark (tests/blender/test_corner_exact.py, the contact test; figures in
// docs/design.md, "Output: a final gather at the corners"). So the plane's radiance at a spot
// q is taken as the point's plus rho (D(q) - D(x)), D the direct light of lamps and emitting
// senders, and each point s* of the sender adds rho_s times the mean of that over cosine
// directions from s* to the plane.
//
// The lit part is a wedge a few per cent of those directions hit, so they must be many and
// cheap: D is evaluated once per cell of a grid around x, even in angle (a penumbra's wedge
// from a box's corner is a range of angles) and in log distance (a contact looks the same at
// every scale), coarse everywhere and fine only where neighbouring coarse values differ; the
// directions cast no ray and spend their weight on the fine cells around their spot: one
// direction per s* leaves the corner's value noisy from seed to seed, and D read at the
// coarse cells' centres alone reads it low (docs/decisions.md, "Figures behind code
// comments").
#include <algorithm>
#include <cmath>

#include "final_gather_trace.h"
#include "radiosity/lights.h"
#include "radiosity/random.h"

namespace radiosity {
namespace fg {

namespace {

// The four cells around (fa, fi), in cell units measured from the first cell's centre, on a
// grid of na angles (wrapping) by nr distances (fi within [0, nr - 1]): f(cell, weight).
template <class F>
void bilinear_cells(double fa, double fi, int na, int nr, F&& f) {
    const int a0 = int(std::floor(fa)), i0 = std::min(nr - 2, int(fi));
    const double ta = fa - a0, ti = fi - i0;
    for (int k = 0; k < 4; ++k) {
        const int a = ((a0 + (k & 1)) % na + na) % na, i = i0 + (k >> 1);
        f(a * nr + i, ((k & 1) ? ta : 1.0 - ta) * ((k >> 1) ? ti : 1.0 - ti));
    }
}

// Per s*, kDirs^2 stratified cosine directions (no rays: they read cells).
constexpr int kDirs = 8;

// The fine cells around x in its plane, even in angle about the normal (from pu toward pv)
// and in log distance from r_min over log_span (DirectVariation::centre gives their centres):
// angles x radii of them, cell (a, i) at a * radii + i.
struct FineCells {
    const Vec3& x;
    const Vec3& pu;
    const Vec3& pv;
    double r_min, log_span;
    int angles, radii;
    // Spends w bilinearly, in (angle, log distance), on the four cells' centres around q.
    void spend(const Vec3& q, const Rgb& w, std::vector<Rgb>& cell_w) const {
        const Vec3 e = q - x;
        const double fi =
            std::clamp(std::log(std::max(length(e), r_min) / r_min) / log_span * radii - 0.5, 0.0, double(radii - 1));
        const double fa = std::atan2(dot(e, pv), dot(e, pu)) / (2.0 * kPi) * angles - 0.5;
        bilinear_cells(fa, fi, angles, radii, [&](int cell, double wc) { cell_w[size_t(cell)] += w * wc; });
    }
};

// Spends each s*'s weight rho_s over kDirs^2 stratified cosine directions about the sender's
// normal sn, each direction's share on the fine cells around the spot q where it meets the
// point's plane (normal n, offset `offset`), if q is within the s*'s reach R (each axis) and
// `inside(q)`. Whether any direction was spent. (Stars: DirectVariation's list of s*.)
template <class Stars, class Inside>
bool spread_directions(const Stars& stars, const Vec3& n, double offset, const Vec3& sn, Rng& rng, const Inside& inside,
                       const FineCells& cells, std::vector<Rgb>& cell_w) {
    Vec3 su, sv;
    frame(sn, su, sv);
    bool any = false;
    for (const auto& st : stars) {
        const double ds = dot(st.p, n) - offset;
        if (!(ds > 0)) continue;
        const Rgb w_dir = st.rho / double(kDirs * kDirs);
        for (int j = 0; j < kDirs * kDirs; ++j) {
            // (The polar number drawn first, then the azimuth's: named, so every compiler draws alike.)
            const double r2 = (j / kDirs + rng.next()) / kDirs;
            const double r1 = (j % kDirs + rng.next()) / kDirs;
            const Vec3 w = cosine_direction(su, sv, sn, r1, r2);
            const double dn = -dot(w, n);
            if (!(dn > 1e-6)) continue;
            const Vec3 q = st.p + w * (ds / dn);
            if (std::abs(q.x - st.p.x) > st.R || std::abs(q.y - st.p.y) > st.R || std::abs(q.z - st.p.z) > st.R) continue;
            if (!inside(q)) continue;
            cells.spend(q, w_dir, cell_w);
            any = true;
        }
    }
    return any;
}

// Marks the coarse cells (angles0 x radii0, sub x sub fine cells each) whose block, or a
// neighbouring one, holds a fine cell with weight: the coarse cells whose D is read.
void mark_read(const std::vector<Rgb>& cell_w, const FineCells& cells, int angles0, int radii0, int sub,
               std::vector<char>& read) {
    for (int a = 0; a < cells.angles; ++a)
        for (int i = 0; i < cells.radii; ++i)
            if (cell_w[size_t(a * cells.radii + i)].max() > 0)
                for (int da = -1; da <= 1; ++da)
                    for (int di = -1; di <= 1; ++di) {
                        const int b = ((a / sub + da) % angles0 + angles0) % angles0, j = i / sub + di;
                        if (j >= 0 && j < radii0) read[size_t(b * radii0 + j)] = 1;
                    }
}

// Marks a valid coarse cell (angles0 x radii0 of them) as on an edge when a valid
// neighbour's dD differs from its own by more than thr in some channel. (Coarse:
// DirectVariation's coarse cell.)
template <class Coarse>
void mark_edges(std::vector<Coarse>& coarse, int angles0, int radii0, double thr) {
    auto differs = [&](const Rgb& u, const Rgb& v) {
        return std::abs(u.r - v.r) > thr || std::abs(u.g - v.g) > thr || std::abs(u.b - v.b) > thr;
    };
    for (int a = 0; a < angles0; ++a)
        for (int i = 0; i < radii0; ++i) {
            Coarse& cl = coarse[size_t(a * radii0 + i)];
            for (int da = -1; da <= 1 && cl.valid && !cl.edge; ++da)
                for (int di = -1; di <= 1 && !cl.edge; ++di) {
                    const int b = ((a + da) % angles0 + angles0) % angles0, j = i + di;
                    if (j < 0 || j >= radii0) continue;
                    const Coarse& nb = coarse[size_t(b * radii0 + j)];
                    cl.edge = nb.valid && differs(cl.dD, nb.dD);
                }
        }
}

}  // namespace

DirectVariation::DirectVariation(const Solution& s, const Config& c, const Point& pt, int near_points, Counts& counts)
    : s_(s),
      c_(c),
      x_(pt.x),
      n_(pt.n),
      own_surface_(s.h.nodes[size_t(pt.leaf)].surface),
      leaf_(pt.leaf),
      counts_(counts),
      radii0_(std::max(2, near_points / 8)),
      sub_(std::clamp(near_points / 8, 2, 4)) {
    const Hierarchy& h = s.h;
    frame(n_, pu_, pv_);
    // The emitters: the senders of the point's records that emit (judged by the sender, not
    // by what x's samples read of it: in a shadow x reads none), an element sender's whole
    // surface (or its object's cluster, when all of it emits) traced once: a lamp of 16 faces
    // refined into elements linked to the point is one lamp to trace, not 30.
    for (const Record& r : pt.records) {
        const Node& src = h.nodes[size_t(r.src)];
        if (!(src.is_cluster() ? h.emits(r.src, Hierarchy::Unknown::Look) : src.emission.max() > 0)) continue;
        int id = r.src;
        if (!src.is_cluster()) {
            id = h.surfaces[size_t(src.surface)].root;
            const std::vector<int>& above = h.ancestors_of_surface(src.surface);
            if (!above.empty() && h.emits(above.back(), Hierarchy::Unknown::Look, true)) id = above.back();
        }
        if (std::find(emitting_.begin(), emitting_.end(), id) == emitting_.end()) emitting_.push_back(id);
        shadow_at_x_ = shadow_at_x_ || r.refined;
    }
}

bool DirectVariation::applies(const std::vector<int>& coplanar, double R) const {
    if (emitting_.empty() && s_.scene.lights().empty()) return false;
    // A shadow's edge crosses the neighbourhood: one at x itself (an emitter's transfer there
    // was traced again for a partial shadow), or the sender's own end within reach (a box's
    // corner: past it the lamp shows). Along a wall's foot, far from its ends, there is none,
    // and most near points are there.
    if (shadow_at_x_) return true;
    // Whether the sender's plane, as far as the polygons `coplanar` show it, ends within R of
    // x: an edge of one of them, not on x's own plane (the contact line), with none past it.
    const Hierarchy& h = s_.h;
    const double x_offset = dot(n_, x_), on_plane = 1e-6 * h.scene_diag, tol = 1e-9 * h.scene_diag;
    const double step = std::max(1e-3 * R, 1e-8 * h.scene_diag);
    for (int id : coplanar) {
        const Node& g = h.nodes[size_t(id)];
        for (int k = 0; k < g.poly.n; ++k) {
            const Vec3& a = g.poly.v[size_t(k)];
            const Vec3& b = g.poly.v[size_t((k + 1) % g.poly.n)];
            if (std::abs(dot(n_, a) - x_offset) <= on_plane && std::abs(dot(n_, b) - x_offset) <= on_plane) continue;
            const Vec3 ab = b - a;
            const double t = std::clamp(dot(x_ - a, ab) / std::max(dot(ab, ab), 1e-300), 0.0, 1.0);
            const Vec3 c = a + ab * t;
            if (length(c - x_) > R) continue;
            Vec3 out = normalize(cross(ab, g.normal));
            if (dot(out, g.center - c) > 0) out = out * -1.0;
            const Vec3 past = c + out * step;
            bool covered = false;
            for (int id2 : coplanar) {
                const Node& g2 = h.nodes[size_t(id2)];
                covered = covered || distance_outside(g2.poly, g2.normal, past) <= tol;
            }
            if (!covered) return true;
        }
    }
    return false;
}

Rgb DirectVariation::direct_at(int leaf, const Vec3& q, uint64_t seed) {
    // D: the lamps' irradiance / pi, and what the emitters send where they are seen, less
    // the near sender's radiance over the same solid angle: where a spot sees more or less of
    // them than x does, it sees less or more of the surfaces around, taken to be as bright as
    // the sender (behind a box's end, what hides the lamp from x is the box's face). So in a
    // furnace, where all is equally bright, D is the same everywhere and the furnace stays
    // exact (taking only the emitters' light would read the cube's corners a little bright:
    // the other wall there is an emitter a hair away, seen more from some spots).
    const Hierarchy& h = s_.h;
    // An eighth of the gather's lamp samples a cell: each cell's value is spent over many
    // directions from many s*, so its noise averages out (docs/decisions.md, "The lamps'
    // variation at a contact: fewer samples a cell").
    const PointLight lamp = direct_light_at(s_.scene, h, s_.vis, q, n_, false, std::max(4, c_.light_samples / 8), seed);
    counts_.rays += lamp.rays;
    Rgb D = lamp.E;
    for (int src : active_) {
        nested_.clear();
        PointRayStream rs(s_.vis);
        point_transfer(h, rs, src, q, n_, leaf, std::max(4, c_.min_rays), Hierarchy::mix(seed, h.nodes[size_t(src)].key),
                       nested_);
        counts_.rays += rs.cast;
        for (const auto& [k, wk] : nested_) D += (h.nodes[size_t(h.live_element(k))].L - L_hidden_) * double(wk);
    }
    return D;
}

bool DirectVariation::eval(const Node& sender, const NearPlane& wall, const Vec3& q, uint64_t seed, Coarse& out) {
    const Hierarchy& h = s_.h;
    if (!in_region(sender, wall, q)) return false;
    const double tol = 1e-9 * h.scene_diag;
    const Node& own_root = h.nodes[size_t(h.surfaces[size_t(own_surface_)].root)];
    const int q_surface = distance_outside(own_root.poly, own_root.normal, q) <= tol ? own_surface_ : wall.surface_at(h, q);
    if (q_surface < 0) return false;
    const int leaf = h.leaf_at(h.surfaces[size_t(q_surface)].root, q);
    if (leaf < 0) return false;
    out.valid = true;
    out.rho = h.rho_at(leaf, q);
    out.dD = direct_at(leaf, q, seed) - D_x_;
    return true;
}

bool DirectVariation::in_region(const Node& sender, const NearPlane& wall, const Vec3& q) {
    return dot(q - sender.poly.v[0], sender.normal) > 0 && wall.region.contains(q);
}

Vec3 DirectVariation::centre(double a, double i, int na, int nr) const {
    const double phi = 2.0 * kPi * (a + 0.5) / na, r = r_min_ * std::exp(log_span_ * (i + 0.5) / nr);
    return x_ + (pu_ * std::cos(phi) + pv_ * std::sin(phi)) * r;
}

Rgb DirectVariation::sum(const Node& sender, const Rgb& L_sender, double d, const NearPlane& wall, uint64_t seed) {
    const int angles0 = kAngles0, angles = kAngles0 * sub_, radii = radii0_ * sub_;
    Rgb total;
    if (stars_.empty()) return total;
    // The emitters but the sender itself (the near field's coupled solve has its light): its
    // surface, and a cluster holding it.
    const Hierarchy& h = s_.h;
    const std::vector<int>& above = h.ancestors_of_surface(sender.surface);
    active_.clear();
    for (int id : emitting_)
        if (id != h.surfaces[size_t(sender.surface)].root && std::find(above.begin(), above.end(), id) == above.end())
            active_.push_back(id);
    if (active_.empty() && s_.scene.lights().empty()) return total;
    L_hidden_ = L_sender;
    D_x_ = direct_at(leaf_, x_, Hierarchy::mix(seed, 0xd0u));
    r_min_ = 0.05 * d;
    log_span_ = std::log(2.0 * kNearReach * d / r_min_);
    // The directions first: each spends its weight (rho_s over the directions) bilinearly, in
    // (angle, log distance), on the four fine cells' centres around its spot.
    cell_w_.assign(size_t(angles * radii), Rgb{});
    Rng rng(Hierarchy::mix(seed, 0xd1ec7u));
    const FineCells cells{x_, pu_, pv_, r_min_, log_span_, angles, radii};
    const auto inside = [&](const Vec3& q) { return in_region(sender, wall, q); };
    if (!spread_directions(stars_, n_, wall.offset, sender.normal, rng, inside, cells, cell_w_)) return total;
    // D at the coarse cells whose block, or a neighbouring one, is read.
    read_.assign(size_t(angles0 * radii0_), 0);
    mark_read(cell_w_, cells, angles0, radii0_, sub_, read_);
    coarse_.assign(size_t(angles0 * radii0_), Coarse{});
    double scale_D = D_x_.max();
    for (int a = 0; a < angles0; ++a)
        for (int i = 0; i < radii0_; ++i) {
            Coarse& cl = coarse_[size_t(a * radii0_ + i)];
            if (read_[size_t(a * radii0_ + i)] &&
                eval(sender, wall, centre(a, i, angles0, radii0_), Hierarchy::mix(seed, uint64_t(3000 + a * radii0_ + i)), cl))
                scale_D = std::max(scale_D, (cl.dD + D_x_).max());
        }
    // A coarse cell is on an edge when a valid neighbour's D differs from its own by 2 %.
    mark_edges(coarse_, angles0, radii0_, 0.02 * scale_D);
    // The fine cells read: D at their own centres on an edge, else bilinear between the
    // valid coarse centres around them.
    for (int a = 0; a < angles; ++a)
        for (int i = 0; i < radii; ++i) {
            const Rgb& w = cell_w_[size_t(a * radii + i)];
            if (!(w.max() > 0)) continue;
            Coarse v;
            if (coarse_[size_t((a / sub_) * radii0_ + i / sub_)].edge) {
                if (!eval(sender, wall, centre(a, i, angles, radii), Hierarchy::mix(seed, uint64_t(9000 + a * radii + i)), v))
                    continue;
            } else {
                const double fa = (a + 0.5) / sub_ - 0.5, fi = std::clamp((i + 0.5) / sub_ - 0.5, 0.0, double(radii0_ - 1));
                double wsum = 0;
                bilinear_cells(fa, fi, angles0, radii0_, [&](int cell, double wc) {
                    const Coarse& cl = coarse_[size_t(cell)];
                    if (cl.valid && wc > 0) v.rho += cl.rho * wc, v.dD += cl.dD * wc, wsum += wc;
                });
                if (!(wsum > 0)) continue;
                v.rho = v.rho / wsum, v.dD = v.dD / wsum;
            }
            total += w * v.rho * v.dD;
        }
    return total;
}

}  // namespace fg
}  // namespace radiosity
