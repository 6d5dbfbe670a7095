// The live drag's placement (live_drag.h): what a drag's first step saves, how a step places
// the dragged objects, and how the solution's placement is put back.
#include "radiosity/live_drag.h"

#include <algorithm>

#include "radiosity/parallel.h"
#include "radiosity/visibility.h"

namespace radiosity {

void LiveDrag::save(const Hierarchy& h, const std::vector<int>& objects, std::vector<std::vector<int>> prims,
                    std::vector<Rigid> poses, int threads) {
    objects_ = objects;
    poses_ = std::move(poses);
    object_prims_ = std::move(prims);
    const std::vector<std::vector<int>>& prims_of = object_prims_;
    boxes_.clear();
    for (size_t j = 0; j < objects.size(); ++j) boxes_.push_back(h.object_box(objects[j], &prims_of[j]));
    ids_.clear();
    // (A stamp per node for this save: objects in one collection share the clusters above
    // them, and an unclustered object's primitives' subtrees are its nodes.)
    if (stamp_.size() < h.nodes.size()) {
        stamp_.resize(h.nodes.size(), 0);
        slot_.resize(h.nodes.size(), -1);
    }
    if (++generation_ == 0) {
        std::fill(stamp_.begin(), stamp_.end(), 0);
        generation_ = 1;
    }
    prims_.clear();
    geoms_.clear();
    summaries_.clear();
    samplers_.clear();
    whole_ = false;
    // (Each object's nodes listed in parallel: a walk of its subtree, a cache miss a node.)
    std::vector<std::vector<int>> own(objects.size());
    parallel_for(objects.size(), threads, [&](size_t j) { own[j] = h.object_nodes(objects[j]); }, 1);
    for (size_t j = 0; j < objects.size(); ++j) {
        const int o = objects[j];
        for (int id : own[j]) keep(id);
        for (int a : h.clusters_above(o)) keep(a);
        const int top = h.object_node[size_t(o)];
        const bool clustered = top >= 0 && h.nodes[size_t(top)].is_cluster();
        if (clustered)
            for (int i = h.nodes[size_t(top)].surf_begin; i < h.nodes[size_t(top)].surf_end; ++i)
                geoms_.emplace_back(i, h.surface_geom[size_t(i)]);
        else
            whole_ = true;
        for (int pi : prims_of[j]) {
            const Primitive& pr = h.prims[size_t(pi)];
            prims_.emplace_back(size_t(pi), pr.poly);
            if (clustered) continue;  // (its cluster's subtree holds its surfaces)
            for (int side : {pr.front, pr.back})
                if (side >= 0) add_subtree(h, h.surfaces[size_t(side)].root);
        }
    }
    nodes_.resize(ids_.size());
    parallel_for(ids_.size(), threads, [&](size_t k) {
        const Node& n = h.nodes[size_t(ids_[k])];
        nodes_[k] = {n.poly, n.normal, n.center, n.box, n.radius, n.area, n.rho_max, n.W, n.is_cluster()};
    }, 512);
    for (size_t k = 0; k < ids_.size(); ++k) {
        if (!nodes_[k].cluster) continue;
        const int id = ids_[k];
        summaries_.emplace_back(id, h.facing_summary[size_t(id)]);
        for (int c = h.sampler_first[size_t(id)]; c < h.sampler_first[size_t(id) + 1]; ++c)
            samplers_.emplace_back(c, h.sampler_records[size_t(c)]);
    }
    area_prefix_.assign(h.area_prefix.begin(), h.area_prefix.end());
    if (whole_) {  // (an unclustered object: placed whole)
        surface_geom_ = h.surface_geom;
        facing_summary_ = h.facing_summary;
        sampler_records_ = h.sampler_records;
    }
}

void LiveDrag::place(Hierarchy& h, Visibility& vis, const std::vector<std::pair<int, Rigid>>& placed, int threads) {
    target_ = &h;
    vis_ = &vis;
    threads_ = threads;
    try {
        for (const auto& op : placed) vis.set_object_transform(op.first, op.second);
        h.place_objects(placed, false, &object_prims_, threads);
        vis.commit();
    } catch (...) {
        settle();
        throw;
    }
}

void LiveDrag::settle() {
    if (!target_) return;
    restore(*target_);
    Visibility& vis = *vis_;
    target_ = nullptr;
    vis_ = nullptr;
    try {
        // (Embree's from the same poses: the same floats.)
        for (size_t j = 0; j < objects_.size(); ++j) vis.set_object_transform(objects_[j], poses_[j]);
        vis.commit();
    } catch (...) {
        lost_ = true;
    }
}

void LiveDrag::restore(Hierarchy& h) {
    parallel_for(ids_.size(), threads_, [&](size_t k) {
        const Saved& v = nodes_[k];
        Node& n = h.nodes[size_t(ids_[k])];
        n.poly = v.poly;
        n.normal = v.normal;
        n.center = v.center;
        n.box = v.box;
        n.radius = v.radius;
        n.area = v.area;
        n.rho_max = v.rho_max;
        n.W = v.W;
    }, 512);
    for (const auto& [i, poly] : prims_) h.prims[i].poly = poly;
    h.area_prefix.swap(area_prefix_);
    if (whole_) {
        h.surface_geom.swap(surface_geom_);
        h.facing_summary.swap(facing_summary_);
        h.sampler_records.swap(sampler_records_);
        return;
    }
    for (auto& [i, g] : geoms_) h.surface_geom[size_t(i)] = g;
    for (auto& [id, f] : summaries_) h.facing_summary[size_t(id)] = std::move(f);
    for (const auto& [k, sc] : samplers_) h.sampler_records[size_t(k)] = sc;
}

void LiveDrag::keep(int id) {
    if (id < 0 || stamp_[size_t(id)] == generation_) return;
    stamp_[size_t(id)] = generation_;
    slot_[size_t(id)] = int(ids_.size());
    ids_.push_back(id);
}

void LiveDrag::add_subtree(const Hierarchy& h, int root) {
    std::vector<int> stack{root};
    while (!stack.empty()) {
        const int id = stack.back();
        stack.pop_back();
        keep(id);
        for (int c : h.nodes[size_t(id)].children) stack.push_back(c);
    }
}

}  // namespace radiosity
