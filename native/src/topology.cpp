// Objects added to and removed from a solved scene (dynamic environments beyond the paper's
// rigid moves). A removal is a move to nowhere: its links die, its Embree instance goes, its
// nodes leave the cluster tree. An addition is a move from nowhere: new primitives, surfaces
// and nodes where a fresh build would put them, a new Embree instance, and links made from the
// clusters above it down, as for a moved object. In both cases the clusters that held the
// object changed shape, so their links are made anew, and env-env links whose rays may pass
// through the object's box are re-evaluated (the AdjustSystem, adjust_system.h, does both for
// all kinds of change).
#include "radiosity/topology.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace radiosity {

namespace {

// The scene slot of a removed object, emptied (its name, cluster and occluder flag stay), and
// its placement back at its geometry as given.
void blank_object(SceneDesc& scene, PendingEdits& edits, int object) {
    ObjectDesc& o = scene.objects_mut()[object];
    ObjectDesc empty;
    empty.name = o.name;
    empty.cluster = o.cluster;
    empty.occluder = o.occluder;
    o = std::move(empty);
    edits.unplace(object);
}

// The cluster path from the root down to `deepest`. Its clusters changed shape: marked in
// ch.inX, they are relinked against their siblings, as the clusters above a moved object are
// (not the root: it has no links).
std::vector<int> changed_chain(const Hierarchy& h, AdjustSystem::Change& ch, int deepest) {
    std::vector<int> chain;
    for (int a = deepest; a >= 0; a = h.nodes[a].parent) chain.push_back(a);
    std::reverse(chain.begin(), chain.end());
    for (int a : chain)
        if (a != h.root) ch.inX[a] = 1;
    return chain;
}

}  // namespace

void Topology::check_live(const SceneDesc& scene, int object, const char* what) const {
    if (object < 0 || object >= int(scene.objects().size()))
        throw InputError(std::string(what) + ": unknown object " + std::to_string(object));
    if (removed(object))
        throw InputError(std::string(what) + ": object '" + scene.objects()[object].name + "' (id " +
                         std::to_string(object) + ") was removed");
}

int Topology::add_cluster(SceneDesc& scene, const std::string& name, int parent) {
    return scene.add_cluster(name, parent);
}

int Topology::add_object(SceneDesc& scene, ObjectDesc object, bool solved) {
    const int id = scene.add_object(std::move(object));  // validates: InputError names the problem
    // Before a first solve (or after a cancelled one) the next solve builds it with the rest.
    if (solved) adds_.push_back(id);
    return id;
}

void Topology::remove_object(SceneDesc& scene, PendingEdits& edits, int object, bool solved) {
    check_live(scene, object, "remove_object");
    if (size_t(object) >= removed_.size()) removed_.resize(size_t(object) + 1, 0);
    removed_[size_t(object)] = 1;
    edits.drop_move(object);
    // Not built into a solution (added and removed before an update, or not solved yet): its
    // slot is emptied now; otherwise the next update takes it out.
    const auto it = std::find(adds_.begin(), adds_.end(), object);
    if (it != adds_.end()) {
        adds_.erase(it);  // the addition is forgotten
    } else if (solved) {
        removes_.push_back(object);
        return;
    }
    blank_object(scene, edits, object);
}

void Topology::commit(SceneDesc& scene, PendingEdits& edits) {
    for (int r : std::exchange(removes_, {})) blank_object(scene, edits, r);
    adds_.clear();  // already in the scene: the full solve builds them
}

bool Topology::outgrows_frame(const SceneDesc& scene, const Hierarchy& h) const {
    if (!pending()) return false;
    // The frame a full solve would derive (hierarchy.cpp: the box of every corner-used vertex
    // as given, placements aside) against the one this solution was built in.
    Aabb all;
    for (size_t oi = 0; oi < scene.objects().size(); ++oi) {
        if (removed(int(oi))) continue;
        const ObjectDesc& d = scene.objects()[oi];
        for (int32_t c : d.corner_verts) all.grow(d.vertices[c]);
    }
    if (all.empty()) return false;  // nothing left: the update handles an empty scene
    // More than twice as coarse or as fine: the minimum element area and the ray offsets,
    // relative to the frame, would differ that much from a fresh solve's. Far-off vertices
    // (1e30) end here too, before they reach Embree as rays it refuses.
    const double d = all.diagonal();
    return !std::isfinite(d) || d > 2.0 * h.unit || d < 0.5 * h.unit;
}

void Topology::apply(const Context& c, AdjustSystem::Change& ch) {
    ch.inX.resize(c.h.nodes.size(), 0);
    remove_objects(c, ch);
    add_objects(c, ch);
    // A later removal in this update may have taken a cluster of an earlier chain with it.
    for (auto& chain : ch.chains) {
        auto dead = std::find_if(chain.begin(), chain.end(), [&c](int a) { return c.h.nodes[a].dead; });
        chain.erase(dead, chain.end());
    }
}

// Removals: the nodes leave the tree, then every link with a dead end goes (the object's own,
// and those of collection clusters it left empty) with the history below it.
void Topology::remove_objects(const Context& c, AdjustSystem::Change& ch) {
    const std::vector<int> removes = std::exchange(removes_, {});
    if (removes.empty()) return;
    Hierarchy& h = c.h;
    for (int r : removes) {
        const Aabb b = h.object_box(r);
        if (!b.empty()) ch.clips.push_back(b);
        const Hierarchy::Removed gone = h.remove_object(r);
        c.stats.element_nodes -= gone.elements;
        ch.chains.push_back(changed_chain(h, ch, gone.deepest));
        c.vis.remove_object(r);
        if (size_t(r) < tri_prim_.size()) tri_prim_[r].clear();
        blank_object(c.scene, c.edits, r);
        ++c.stats.objects_removed;
    }
    std::vector<int> doomed;
    for (size_t i = 0; i < c.links.size(); ++i) {
        const Link& l = c.links[i];
        if (l.dead || !(h.nodes[l.src].dead || h.nodes[l.rcv].dead)) continue;
        if (l.active) ++c.stats.links_removed;
        doomed.push_back(int(i));
    }
    for (int i : doomed) c.links.kill(h, i);  // dead nodes' link lists are empty already: no harm
}

// Additions: each object's nodes where a fresh build puts them, its own Embree instance, and
// the links to make for it in `ch`; every new node is marked in ch.inX.
void Topology::add_objects(const Context& c, AdjustSystem::Change& ch) {
    Hierarchy& h = c.h;
    const size_t no = c.scene.objects().size();
    c.edits.fit_poses(no);
    tri_prim_.resize(no);
    const size_t first_new_node = h.nodes.size();
    for (int a : std::exchange(adds_, {})) {
        const size_t first_prim = h.prims.size(), first_surface = h.surfaces.size();
        const int top = h.add_object(c.scene, a, c.settings.use_clustering);
        c.stats.element_nodes += int64_t(h.surfaces.size() - first_surface);
        ch.inX.resize(h.nodes.size(), 0);
        // Its own Embree instance, placed as given (identity pose).
        std::vector<int> prims(h.prims.size() - first_prim);
        for (size_t k = 0; k < prims.size(); ++k) prims[k] = int(first_prim + k);
        add_geometry(c.scene, h, c.vis, a, prims);
        const Aabb b = h.object_box(a);
        if (!b.empty()) ch.clips.push_back(b);
        ++c.stats.objects_added;
        if (h.surfaces.size() == first_surface) continue;  // only zero-area polygons
        if (h.object_node[a] >= 0) {
            // Linked like a moved object, cluster pairs first, from where it hangs; its
            // inside (what the root's self-link gives it in a full solve) from its own
            // self-link, or that of the new collection cluster it came with.
            ch.chains.push_back(changed_chain(h, ch, h.object_node[a]));
            ch.seeds.push_back({top, top, -1});
        } else {
            // Unclustered: each new surface with every other surface below the root.
            std::vector<int> fresh;
            for (size_t si = first_surface; si < h.surfaces.size(); ++si) fresh.push_back(h.surfaces[si].root);
            for (int r : fresh)
                for (int k : h.nodes[h.root].children) {
                    if (k == r) continue;
                    ch.seeds.push_back({k, r, -1});
                    if (size_t(k) < first_new_node) ch.seeds.push_back({r, k, -1});
                }
        }
    }
    ch.inX.resize(h.nodes.size(), 0);
    for (size_t id = first_new_node; id < h.nodes.size(); ++id) ch.inX[id] = 1;
}

void Topology::build_geometry(const SceneDesc& scene, const Hierarchy& h, Visibility& vis,
                              const std::vector<std::vector<int>>& prims_of) {
    tri_prim_.assign(scene.objects().size(), {});
    for (size_t o = 0; o < scene.objects().size(); ++o) add_geometry(scene, h, vis, int(o), prims_of[o]);
}

void Topology::add_geometry(const SceneDesc& scene, const Hierarchy& h, Visibility& vis, int o,
                            const std::vector<int>& prims) {
    std::vector<Vec3> tv;
    for (int pi : prims) {
        const Primitive& p = h.prims[size_t(pi)];
        tv.insert(tv.end(), {p.poly.v[0], p.poly.v[1], p.poly.v[2]});
        tri_prim_[size_t(o)].push_back(pi);
        if (p.poly.n == 4) {
            tv.insert(tv.end(), {p.poly.v[0], p.poly.v[2], p.poly.v[3]});
            tri_prim_[size_t(o)].push_back(pi);
        }
    }
    if (!scene.objects()[size_t(o)].occluder) tv.clear();  // lights.h: area lights cast no shadow
    vis.add_object(o, tv);
}

std::vector<int> Topology::own_prims(int object) const {
    // (A quad's two triangles name it twice, one after the other.)
    std::vector<int> own;
    for (int pi : tri_prim_[size_t(object)])
        if (own.empty() || own.back() != pi) own.push_back(pi);
    return own;
}

}  // namespace radiosity
