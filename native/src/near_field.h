// The final gather's near field, private to its sources (near_field.cpp, near_direct.cpp,
// final_gather_trace.h): what a point of a sender a hair from an output point sees of the
// output point's own plane (NearPlane), the plane's direct-light term (DirectVariation), one
// point's near field (NearField) and the lists it reuses from point to point (NearScratch).
#pragma once
#include <optional>
#include <utility>
#include <vector>

#include "radiosity/final_gather.h"
#include "radiosity/random.h"
#include "radiosity/transfer.h"

namespace radiosity {
namespace fg {

using Solution = FinalGather::Solution;
using Config = FinalGather::Config;
using Counts = FinalGather::Counts;
struct Point;  // final_gather_trace.h
struct Run;

// Near field (near_field): a sender's part within kNearReach x d of a point at distance d.
constexpr double kNearReach = 20.0;

// The plane of the surface a point lies on, as a point of a sender near it sees it: what
// its samples read there (per surface of that plane), then the coupling F of the part of
// the plane near the sender's point and the radiance its samples read over that part
// (WL, weighted by F). The two sides of a contact light each other there (near_field).
struct NearPlane {
    Vec3 n;
    double offset = 0, tol = 0;
    // Only the plane's part here is coupled: where the point's radiance stands for it
    // (in front of the sender's polygons); past it s* reads points gathered there.
    Aabb region;
    double F = 0, F_all = 0;   // in the region; within s*'s reach (20 x its distance)
    Rgb WL, WL_all;
    std::vector<std::pair<int, std::pair<double, Rgb>>> seen;  // surface, (weight, weighted L)
    std::vector<int> surfaces;  // the plane's surfaces met near any s* of one sender
    void read(const Hierarchy& h, const Node& k, double w);
    void couple(const Hierarchy& h, const Vec3& sp, const Vec3& sn);
    // The first of `surfaces` whose polygon holds q (a point of the plane), or -1.
    int surface_at(const Hierarchy& h, const Vec3& q) const;
};

// The near field's direct-light term (near_direct.cpp): the point's plane near a sender
// a hair away is the point's radiance plus rho (D(q) - D(x)) there, D the direct light of
// lamps and emitting senders, as the sender's points s* see it.
class DirectVariation {
public:
    DirectVariation(const Solution& s, const Config& c, const Point& pt, int near_points, Counts& counts);
    // Whether the term can matter for a sender whose plane the point sees as the surface
    // roots `coplanar`, within reach R: a shadow's edge near x.
    bool applies(const std::vector<int>& coplanar, double R) const;
    void clear_stars() { stars_.clear(); }
    void add_star(const Vec3& p, const Rgb& rho, double R) { stars_.push_back({p, rho, R}); }
    // Over the s* added: sum of rho_s x the mean over cosine directions from s* of
    // rho (D(q) - D(x)) at the spot q where each meets the point's plane in `wall`'s region.
    // L_sender: the sender's radiance as the point reads it (what hides an emitter).
    Rgb sum(const Node& sender, const Rgb& L_sender, double d, const NearPlane& wall, uint64_t seed);

private:
    struct Star { Vec3 p; Rgb rho; double R; };
    struct Coarse { bool valid = false, edge = false; Rgb rho, dD; };
    Rgb direct_at(int leaf, const Vec3& q, uint64_t seed);
    bool eval(const Node& sender, const NearPlane& wall, const Vec3& q, uint64_t seed, Coarse& out);
    static bool in_region(const Node& sender, const NearPlane& wall, const Vec3& q);
    Vec3 centre(double a, double i, int na, int nr) const;
    static constexpr int kAngles0 = 8;
    const Solution& s_;
    const Config& c_;
    Vec3 x_, n_, pu_, pv_;
    int own_surface_, leaf_;
    Counts& counts_;
    int radii0_, sub_;  // coarse cells in log distance; fine cells per coarse one, each way
    std::vector<int> emitting_;  // node ids: emitting surface roots and clusters
    std::vector<int> active_;    // ... but the sender's own, for one sum()
    Rgb L_hidden_, D_x_;
    bool shadow_at_x_ = false;
    std::vector<Star> stars_;
    double r_min_ = 0, log_span_ = 0;
    std::vector<Rgb> cell_w_;  // fine cells: rho_s x the share of the directions read
    std::vector<char> read_;
    std::vector<Coarse> coarse_;
    std::vector<std::pair<int, float>> nested_;
};

// The near field's lists, kept by one thread from point to point (Scratch).
struct NearScratch {
    // What the point's samples read of one surface: visible weight, weighted radiance, and
    // the weighted sum of the sizes of the leaves read.
    struct Seen { int surface; double W; Rgb WL; double WS; };
    // A point s* found on a sender, in its stratum of the point's hemisphere.
    struct Candidate { int stratum; Vec3 p; int leaf; };
    // radiance_at's estimate of what a link may bring: coupling, sender radiance.
    struct Estimate { double F, L; };
    std::vector<Seen> seen;
    std::vector<int> seen_index;  // per surface: its entry in `seen`, or -1 (reset after each point)
    NearPlane wall;
    std::vector<int> coplanar;
    std::vector<Vec3> stars;
    std::vector<Candidate> found;
    std::vector<std::pair<int, bool>> reaching;
    std::vector<std::pair<int, float>> nested;
    std::vector<Estimate> est;
};

// One output point's near field (near_field.cpp): for each sender a hair from the point, its
// part near the point read at points s* of it, and the correction that makes to the point's
// irradiance / pi.
class NearField {
public:
    NearField(const Run& run, const Point& pt, Counts& counts, NearScratch& scratch);
    // Adds each near sender's correction to `near`, in the order the point's samples read them.
    void add_to(Rgb& near);

private:
    using Seen = NearScratch::Seen;
    // Over one sender's s*: what they gather less the point's plane (B0), their coupling to
    // the plane near the point (C) and beyond it (Cout, with Bout its leaves' radiance).
    struct Stars { Rgb B0, C, Cout, Bout; int got = 0; };
    void read_surfaces();
    // The point's irradiance / pi without the correction, as values() makes it (lamps,
    // samples, closure; exact in a furnace, where the correction must then vanish).
    Rgb uncorrected() const;
    // Whether the sender (surface root `root`) lies near: its distance d, the coupling of its
    // part within kNearReach x d, and the box around the point that bounds that part.
    bool near_part(const Seen& sn, const Node& root, double& d, double& F_near, Aabb& box) const;
    // The point's plane as the s* see it: the region the point stands for, the coplanar roots.
    void bound_wall(const Node& root, double R);
    Stars gather_stars(const Seen& sn, const Node& root, double d, double R, bool vary, uint64_t seed, Rng& rng);
    bool beyond(const Node& root, const Aabb& box, uint64_t seed, Rng& rng, Rgb& mean);
    // One sender's correction; false when it is not near or no s* was found on it.
    bool correction(const Seen& sn, Rgb& out);

    const Run& run_;
    const Hierarchy& h_;
    const Point& pt_;
    Counts& counts_;
    const Node& own_;
    // Points s* per near sender: the light there can change within a hair (the shadow's edge
    // that starts at a box's foot), so they are many, each gathered with few rays: a share of
    // the point's own budget (DRAFT 4, MEDIUM 16, HIGH 32); drawn over side_ x side_ strata,
    // of which about max_stars_ gather where many meet the sender (gather_stars).
    const int near_points_, side_, max_stars_;
    NearScratch& scratch_;
    std::vector<Seen>& seen_;
    NearPlane& wall_;
    std::vector<int>& coplanar_;
    std::vector<Vec3>& stars_;
    std::optional<DirectVariation> direct_;  // made for the first near sender
    Rgb S_;
};

// Outgoing radiance at a point sp of leaf m_id, gathered there (lamps and m's links); with
// `wall`, also what it gathers of that plane near sp.
Rgb radiance_at(const Run& run, int m_id, const Vec3& sp, uint64_t seed, Counts& counts, NearScratch& scratch,
                NearPlane* wall = nullptr);
// Adds to pt.near the corrections of the senders a hair from the point.
void near_field(const Run& run, Point& pt, Counts& counts, NearScratch& scratch);

}  // namespace fg
}  // namespace radiosity
