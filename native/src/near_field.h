// The final gather's near field, private to the solver's sources (near_field.cpp,
// near_direct.cpp): what a point of a sender a hair from an output point sees of the output
// point's own plane (NearPlane), and the plane's direct-light term (DirectVariation).
#pragma once
#include <utility>
#include <vector>

#include "radiosity/final_gather.h"
#include "final_gather_trace.h"

namespace radiosity {

// The plane of the surface a point lies on, as a point of a sender near it sees it: what
// its samples read there (per surface of that plane), then the coupling F of the part of
// the plane near the sender's point and the radiance its samples read over that part
// (WL, weighted by F). The two sides of a contact light each other there (near_field).
struct FinalGather::NearPlane {
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
class FinalGather::DirectVariation {
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
    bool cluster_emits(const Node& cl, bool all = false) const;  // any (or all) of its surfaces
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

}  // namespace radiosity
