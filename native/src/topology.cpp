// Objects added to and removed from a solved scene (dynamic environments beyond the paper's
// rigid moves). A removal is a move to nowhere: its links die, its Embree instance goes, its
// nodes leave the cluster tree. An addition is a move from nowhere: new primitives, surfaces
// and nodes where a fresh build would put them, a new Embree instance, and links made from the
// clusters above it down, as for a moved object. In both cases the clusters that held the
// object changed shape, so their links are made anew, and env-env links whose rays may pass
// through the object's box are re-evaluated (the AdjustSystem, adjust_system.h, does both for
// all kinds of change).
#include <algorithm>
#include <cmath>

#include "radiosity/solver.h"

namespace radiosity {

void Solver::check_live(int object, const char* what) const {
    if (object < 0 || object >= int(scene_.objects().size()))
        throw InputError(std::string(what) + ": unknown object " + std::to_string(object));
    if (removed(object))
        throw InputError(std::string(what) + ": object '" + scene_.objects()[object].name + "' (id " +
                         std::to_string(object) + ") was removed");
}

int Solver::add_cluster(const std::string& name, int parent) {
    settle_preview();
    return scene_.add_cluster(name, parent);
}

int Solver::add_object(ObjectDesc object) {
    settle_preview();
    const int id = scene_.add_object(std::move(object));  // validates: InputError names the problem
    // Before a first solve (or after a cancelled one) the next solve builds it with the rest.
    if (solved_) edits_.record_add(id);
    return id;
}

void Solver::remove_object(int object) {
    settle_preview();
    check_live(object, "remove_object");
    // Not built into a solution (added and removed before an update, or not solved yet): its
    // slot is emptied now; otherwise the next update takes it out.
    if (!edits_.record_remove(object, solved_)) blank_object(object);
}

void Solver::blank_object(int object) {
    ObjectDesc& o = scene_.objects_mut()[object];
    ObjectDesc empty;
    empty.name = o.name;
    empty.cluster = o.cluster;
    empty.occluder = o.occluder;
    o = std::move(empty);
    edits_.unplace(object);
}

void Solver::commit_topology() {
    for (int r : edits_.take_removes()) blank_object(r);
    edits_.take_adds();  // already in scene_: the full solve builds them
}

bool Solver::changes_outgrow_frame() const {
    if (!edits_.topology()) return false;
    // The frame a full solve would derive (hierarchy.cpp: the box of every corner-used vertex
    // as given, placements aside) against the one this solution was built in.
    Aabb all;
    for (size_t oi = 0; oi < scene_.objects().size(); ++oi) {
        if (removed(int(oi))) continue;
        const ObjectDesc& d = scene_.objects()[oi];
        for (int32_t c : d.corner_verts) all.grow(d.vertices[c]);
    }
    if (all.empty()) return false;  // nothing left: the update handles an empty scene
    // More than twice as coarse or as fine: the minimum element area and the ray offsets,
    // relative to the frame, would differ that much from a fresh solve's. Far-off vertices
    // (1e30) end here too, before they reach Embree as rays it refuses.
    const double d = all.diagonal();
    return !std::isfinite(d) || d > 2.0 * h_.unit || d < 0.5 * h_.unit;
}

void Solver::apply_topology(Change& ch) {
    ch.inX.resize(h_.nodes.size(), 0);
    remove_objects(ch);
    add_objects(ch);
    // A later removal in this update may have taken a cluster of an earlier chain with it.
    for (auto& chain : ch.chains) {
        auto dead = std::find_if(chain.begin(), chain.end(), [this](int a) { return h_.nodes[a].dead; });
        chain.erase(dead, chain.end());
    }
    refit_tolerances();
    // The direct light of every leaf may have a new shadow (or lost one), as after a move;
    // contacts refer to surfaces that may be gone.
    direct_light_.relight();
    direct_light_.forget_contacts();
}

// The cluster path from the root down to `deepest`. Its clusters changed shape: marked in
// ch.inX, they are relinked against their siblings, as the clusters above a moved object are
// (not the root: it has no links).
std::vector<int> Solver::changed_chain(Change& ch, int deepest) const {
    std::vector<int> chain;
    for (int a = deepest; a >= 0; a = h_.nodes[a].parent) chain.push_back(a);
    std::reverse(chain.begin(), chain.end());
    for (int a : chain)
        if (a != h_.root) ch.inX[a] = 1;
    return chain;
}

// Removals: the nodes leave the tree, then every link with a dead end goes (the object's own,
// and those of collection clusters it left empty) with the history below it.
void Solver::remove_objects(Change& ch) {
    const std::vector<int> removes = edits_.take_removes();
    if (removes.empty()) return;
    for (int r : removes) {
        const Aabb b = h_.object_box(r);
        if (!b.empty()) ch.clips.push_back(b);
        for (int id : h_.object_nodes(r))
            if (!h_.nodes[id].is_cluster()) --stats_.element_nodes;
        ch.chains.push_back(changed_chain(ch, h_.remove_object(r)));
        vis_->remove_object(r);
        if (size_t(r) < tri_prim_.size()) tri_prim_[r].clear();
        blank_object(r);
        ++stats_.objects_removed;
    }
    std::vector<int> doomed;
    for (size_t i = 0; i < links_.size(); ++i) {
        const Link& l = links_[i];
        if (l.dead || !(h_.nodes[l.src].dead || h_.nodes[l.rcv].dead)) continue;
        if (l.active) ++stats_.links_removed;
        doomed.push_back(int(i));
    }
    for (int i : doomed) links_.kill(h_, i);  // dead nodes' link lists are empty already: no harm
}

// Additions: each object's nodes where a fresh build puts them, its own Embree instance, and
// the links to make for it in `ch`; every new node is marked in ch.inX.
void Solver::add_objects(Change& ch) {
    const size_t no = scene_.objects().size();
    edits_.fit_poses(no);
    tri_prim_.resize(no);
    const size_t first_new_node = h_.nodes.size();
    for (int a : edits_.take_adds()) {
        const size_t first_prim = h_.prims.size(), first_surface = h_.surfaces.size();
        const int top = h_.add_object(scene_, a, settings_.use_clustering);
        stats_.element_nodes += int64_t(h_.surfaces.size() - first_surface);
        ch.inX.resize(h_.nodes.size(), 0);
        // Its own Embree instance, placed as given (identity pose).
        std::vector<int> prims(h_.prims.size() - first_prim);
        for (size_t k = 0; k < prims.size(); ++k) prims[k] = int(first_prim + k);
        add_object_geometry(a, prims);
        const Aabb b = h_.object_box(a);
        if (!b.empty()) ch.clips.push_back(b);
        ++stats_.objects_added;
        if (h_.surfaces.size() == first_surface) continue;  // only zero-area polygons
        if (h_.object_node[a] >= 0) {
            // Linked like a moved object, cluster pairs first, from where it hangs; its
            // inside (what the root's self-link gives it in a full solve) from its own
            // self-link, or that of the new collection cluster it came with.
            ch.chains.push_back(changed_chain(ch, h_.object_node[a]));
            ch.seeds.push_back({top, top, -1});
        } else {
            // Unclustered: each new surface with every other surface below the root.
            std::vector<int> fresh;
            for (size_t si = first_surface; si < h_.surfaces.size(); ++si) fresh.push_back(h_.surfaces[si].root);
            for (int r : fresh)
                for (int c : h_.nodes[h_.root].children) {
                    if (c == r) continue;
                    ch.seeds.push_back({c, r, -1});
                    if (size_t(c) < first_new_node) ch.seeds.push_back({r, c, -1});
                }
        }
    }
    ch.inX.resize(h_.nodes.size(), 0);
    for (size_t id = first_new_node; id < h_.nodes.size(); ++id) ch.inX[id] = 1;
}

// The scene's size changed (changes_outgrow_frame() allows up to 2x): the tolerances a fresh
// solve derives from it (smallest element area, ray offsets) follow, so refinement from here
// on stops where a fresh solve's does (the frame itself stays): without it, many objects added
// at once to a small scene refine further than a fresh solve of the same scene would.
void Solver::refit_tolerances() {
    Aabb box;
    for (const Primitive& p : h_.prims)
        if (p.object >= 0)
            for (int k = 0; k < p.poly.n; ++k) box.grow(p.poly.v[k]);
    if (box.empty() || !(box.diagonal() > 0)) return;
    h_.scene_box = box;
    h_.scene_diag = box.diagonal();
    min_area_ = settings_.min_area_fraction * h_.scene_diag * h_.scene_diag;
    fit_ray_epsilon();
}

}  // namespace radiosity
