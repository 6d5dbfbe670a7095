// The live drag's placement: between the steps of one drag the dragged objects stay where
// the last step put them (in the hierarchy and in Embree), so that the next step goes on from
// there; anything else that reads or changes the solution first puts the solution's placement
// back (settle), bit for bit. LiveDrag owns what a drag rewrote and where it was; the preview
// itself (what a step re-traces) is FinalGather's (preview.cpp).
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "radiosity/hierarchy.h"
#include "radiosity/rigid.h"

namespace radiosity {

class Visibility;

class LiveDrag {
public:
    // Saves the solution's geometry of `objects` before a drag's first step places them:
    // per object its primitives (`prims`) and its placement (`poses`, Embree's), and the
    // hierarchy's nodes, primitives and tables that placing them rewrites
    // (Hierarchy::place_objects, not whole). Placing them again from the rest geometry would
    // not give the same bits (children's normals are their parents' when built, recomputed
    // when placed), so settle() copies these back.
    void save(const Hierarchy& h, const std::vector<int>& objects, std::vector<std::vector<int>> prims,
              std::vector<Rigid> poses, int threads);
    // Places a step's objects (those saved, in `placed`'s order) in `h` and `vis` and holds
    // them there until settle(); a failure on the way puts them back at once and throws.
    void place(Hierarchy& h, Visibility& vis, const std::vector<std::pair<int, Rigid>>& placed, int threads);
    // Puts back the solution's placement if a step holds one. An Embree failure on the way
    // leaves rays as the step placed them: lost() says so from then on.
    void settle();
    // A step's placement is held (the hierarchy and Embree are not the solution's).
    bool holds() const { return target_ != nullptr; }
    // Embree could not take back a step's placement: the solution must not be trusted.
    bool lost() const { return lost_; }
    // Puts back a step's placement (settle) and frees the drag's memory (made again at the
    // next drag's first step); lost() is cleared.
    void forget() {
        settle();
        *this = LiveDrag{};
    }

    // The objects saved, in the order given, with their primitives and their boxes as solved.
    const std::vector<int>& objects() const { return objects_; }
    const std::vector<std::vector<int>>& prims() const { return object_prims_; }
    const Aabb& box(size_t j) const { return boxes_[j]; }
    // A saved node's polygon and normal as solved.
    const Poly& poly(int node) const { return nodes_[size_t(slot_[size_t(node)])].poly; }
    const Vec3& normal(int node) const { return nodes_[size_t(slot_[size_t(node)])].normal; }

private:
    void keep(int id);
    void add_subtree(const Hierarchy& h, int root);
    void restore(Hierarchy& h);
    struct Saved {
        Poly poly;
        Vec3 normal, center;
        Aabb box;
        double radius, area, rho_max;
        decltype(Node::W) W;
        bool cluster;
    };
    // Where a step's placement is held (null: nowhere), and the threads to put it back with.
    Hierarchy* target_ = nullptr;
    Visibility* vis_ = nullptr;
    int threads_ = 0;
    bool lost_ = false;
    std::vector<int> ids_;      // the nodes saved
    std::vector<Saved> nodes_;  // ... and what was saved of each
    std::vector<uint32_t> stamp_;  // per node: the save that took it
    std::vector<int> slot_;        // ... and its place in ids_
    uint32_t generation_ = 0;
    std::vector<int> objects_;
    std::vector<std::vector<int>> object_prims_;
    std::vector<Rigid> poses_;  // per object saved: its placement as solved
    std::vector<Aabb> boxes_;
    std::vector<std::pair<size_t, Poly>> prims_;
    std::vector<std::pair<int, SurfaceGeom>> geoms_;
    std::vector<std::pair<int, Hierarchy::FacingSummary>> summaries_;
    std::vector<std::pair<int, Hierarchy::SamplerRecord>> samplers_;
    std::vector<double> area_prefix_;
    bool whole_ = false;
    std::vector<SurfaceGeom> surface_geom_;
    std::vector<Hierarchy::FacingSummary> facing_summary_;
    std::vector<Hierarchy::SamplerRecord> sampler_records_;
};

}  // namespace radiosity
