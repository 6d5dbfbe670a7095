// Topology: which objects the solution holds. It records the objects added to and removed from
// a solved scene until an update builds them into the solution or takes them out (or a full
// solve starts over), keeps which objects were removed (their ids stay, their slots empty), and
// holds each object's triangles as Embree has them, with the primitive each one belongs to.
// It keeps no reference into the solver: the scene, the hierarchy, Embree, the links, the
// placements and the stats it changes are handed to each call.
#pragma once
#include <string>
#include <vector>

#include "radiosity/adjust_system.h"
#include "radiosity/hierarchy.h"
#include "radiosity/link_store.h"
#include "radiosity/pending_edits.h"
#include "radiosity/scene.h"
#include "radiosity/settings.h"
#include "radiosity/stats.h"
#include "radiosity/visibility.h"

namespace radiosity {

class Topology {
public:
    // --- Edits between bakes. `solved`: a solution holds the scene's objects (an update must
    // build or remove them); before a first solve, the solve takes the scene as it is.
    // A new collection cluster (SceneDesc::add_cluster: InputError for an unknown parent).
    int add_cluster(SceneDesc& scene, const std::string& name, int parent);
    // Validates and appends `object` to `scene` (SceneDesc::add_object); returns its id.
    int add_object(SceneDesc& scene, ObjectDesc object, bool solved);
    // Marks `object` removed and forgets its pending move. One still pending as an addition,
    // or not built into a solution, has its slot emptied at once; the rest wait for an update.
    void remove_object(SceneDesc& scene, PendingEdits& edits, int object, bool solved);
    // InputError naming `what` for an unknown id or an object removed already.
    void check_live(const SceneDesc& scene, int object, const char* what) const;
    bool removed(int object) const { return object >= 0 && size_t(object) < removed_.size() && removed_[size_t(object)]; }
    bool pending() const { return !adds_.empty() || !removes_.empty(); }  // additions or removals

    // --- Taken by a full solve or an update.
    // Before a full solve: pending removals leave the scene (their slots emptied); pending
    // additions are in the scene already, and the solve builds them.
    void commit(SceneDesc& scene, PendingEdits& edits);
    // Whether the pending additions and removals change the scene's size by more than 2x:
    // the internal frame and the tolerances relative to it would then differ from a fresh
    // solve's, which the update cannot follow.
    bool outgrows_frame(const SceneDesc& scene, const Hierarchy& h) const;
    // What applying the pending changes reads and changes, held for one call.
    struct Context {
        SceneDesc& scene;        // a removed object's slot emptied
        Hierarchy& h;            // nodes taken out and built
        Visibility& vis;         // triangles taken out and added (committed by the caller)
        LinkStore& links;        // links with a dead end killed
        PendingEdits& edits;     // a removed object's placement dropped, an added one's slot made
        const Settings& settings;
        Stats& stats;            // objects and elements added and removed, links removed
    };
    // Removals, then additions, into the hierarchy, Embree and the links; `ch` (the update's
    // change, adjust_system.h) gets their boxes, the cluster paths that changed shape, the
    // nodes they made (inX) and the links to make for an added object.
    void apply(const Context& c, AdjustSystem::Change& ch);

    // --- Each object's triangles in Embree (quads as two).
    // A full solve's fresh Embree scene: object o's primitives `prims_of[o]`, every object.
    void build_geometry(const SceneDesc& scene, const Hierarchy& h, Visibility& vis,
                        const std::vector<std::vector<int>>& prims_of);
    // An object's primitives, in order.
    std::vector<int> own_prims(int object) const;
    // Per object: Embree triangle -> primitive (what a ray's hit is on).
    const std::vector<std::vector<int>>& tri_prim() const { return tri_prim_; }

private:
    // An object's triangles (its primitives, quads as two) into Embree and tri_prim_.
    void add_geometry(const SceneDesc& scene, const Hierarchy& h, Visibility& vis, int object,
                      const std::vector<int>& prims);
    // apply's parts.
    void remove_objects(const Context& c, AdjustSystem::Change& ch);
    void add_objects(const Context& c, AdjustSystem::Change& ch);

    std::vector<int> adds_, removes_;  // pending, in the order recorded
    std::vector<char> removed_;  // per object (grown as objects are removed): its slot stays, empty
    std::vector<std::vector<int>> tri_prim_;  // per object: Embree triangle -> primitive
};

}  // namespace radiosity
