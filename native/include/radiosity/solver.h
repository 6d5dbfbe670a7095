// The clustering-based hierarchical radiosity solver: initial linking from the root cluster
// down (3.1.1), BF-style refinement with the 3.5 criterion, iterative gathering with
// push-pull, and per-corner output. Solver is what the Python module drives: it owns the
// scene, the hierarchy, the links and the parts that work on them, and runs a full solve, an
// incremental update after edits (moves, additions, removals, materials) and the live preview.
#pragma once
#include <array>
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

#include "radiosity/adjust_system.h"
#include "radiosity/direct_light.h"
#include "radiosity/final_gather.h"
#include "radiosity/gathering.h"
#include "radiosity/hierarchy.h"
#include "radiosity/leaf_mesh.h"
#include "radiosity/lights.h"
#include "radiosity/link.h"
#include "radiosity/link_store.h"
#include "radiosity/live_drag.h"
#include "radiosity/memory_budget.h"
#include "radiosity/oracle.h"
#include "radiosity/pending_edits.h"
#include "radiosity/pockets.h"
#include "radiosity/refinement.h"
#include "radiosity/rigid.h"
#include "radiosity/run_clock.h"
#include "radiosity/scene.h"
#include "radiosity/settings.h"
#include "radiosity/stats.h"
#include "radiosity/topology.h"
#include "radiosity/visibility.h"

namespace radiosity {

struct Cancelled : std::runtime_error {
    Cancelled() : std::runtime_error("cancelled") {}
};

// Progress reporting and cancellation, shared with a job thread.
struct Control {
    std::atomic<double> fraction{0.0};
    std::atomic<bool> cancel{false};
};

// Some corners of one object and their new values (RGB interleaved).
struct CornerPatch {
    int object = -1;
    std::vector<int32_t> corners;
    std::vector<float> values;
};

class Solver {
public:
    Solver(SceneDesc scene, Settings settings);

    // Full solve from scratch. Throws Cancelled when control->cancel is set.
    void solve(Control* control = nullptr);
    // (Not when a drag step's placement could not be taken back: LiveDrag::lost.)
    bool solved() const { return solved_ && !drag_.lost(); }

    // Outgoing radiance of the front side at every Blender corner of the object, RGB
    // interleaved (corner_count * 3).
    std::vector<float> corner_radiance(int object) const;
    // corner_radiance of every object, in object order, concatenated.
    std::vector<float> all_corner_radiance() const;
    // Radiance of the front side at one point of a polygon, from the leaf containing it.
    Rgb radiance_at(int object, int face, const Vec3& p) const;

    // --- Dynamic environments (adjust.cpp). Moves and material changes are recorded, then
    // update() runs AdjustSystem and a warm-started re-solve.
    // Rigid placement of an object relative to its geometry as given (row-major 4x4, world
    // units). Throws InputError for NaN, non-rigid or mirroring matrices.
    void move_object(int object, const std::array<double, 16>& m);
    // Per polygon (or one value for the whole object).
    void set_emission(int object, const std::vector<Rgb>& values);
    void set_reflectance(int object, const std::vector<Rgb>& values);
    // Per corner (ObjectDesc::corner_reflectance / corner_emission; empty: the polygon's). Only
    // the output reads them: no update() is needed, the next corner_radiance uses them.
    void set_corner_materials(int object, std::vector<Rgb> reflectance, std::vector<Rgb> emission);
    // A texture's pieces inside the polygons (ObjectDesc::pieces, with their emission when
    // `emit`; empty: uniform polygons). The elements take them at the next update().
    void set_texture_pieces(int object, std::vector<TexturePiece> pieces, bool emit = false);
    // Objects added and removed (Topology, topology.h), applied by the next update() like
    // moves: an addition is linked into the kept solution, a removal's links and nodes go;
    // env-env links whose rays pass through the object's box are re-evaluated. Ids stay stable:
    // a new object gets the next id, a removed one keeps its slot (empty: no corners) and is
    // never reused.
    // Validates like SceneDesc::add_object (InputError); vertices in world space, placed as
    // given (later moves are relative to that). The cluster may be one made by add_cluster.
    int add_object(ObjectDesc object);
    // InputError for an unknown id or an object removed already.
    void remove_object(int object);
    // A new collection cluster (for objects added later); InputError for an unknown parent.
    int add_cluster(const std::string& name, int parent = -1);
    bool removed(int object) const { return topology_.removed(object); }

    // Live drag (preview.cpp): the corners whose colour changes, and their values, with the
    // objects in `moves` placed there (move_object's matrices, validated alike): the direct
    // light re-traced at the new places, the rest as solved (FinalGather::preview); every
    // other corner keeps corner_radiance's value. The solution and pending moves stay as they
    // were, bit for bit; so do the dragged objects' placements (Embree's and the hierarchy's)
    // as every other call reads them: the next step of the same drag finds them where this one
    // left them, anything else puts them back first. Without a final gather (gather_rays 0) or a solution: logic_error.
    // A step does about `work` (Settings::preview_work when negative; 0: all there is), the
    // points nearest the dragged objects first; the others keep what earlier steps showed.
    std::vector<CornerPatch> preview(const std::map<int, std::array<double, 16>>& moves,
                                     FinalGather::PreviewCounts* counts = nullptr, int64_t work = -1);

    // Incremental update of the kept solution (a full solve if there is none).
    void update(Control* control = nullptr);

    const Stats& stats() const { return stats_; }
    // What the solution holds of each object, in object order (costs.cpp): its output points'
    // rays in the last final gather (a solve's, or an update's), and its links with the rest of
    // the scene as they stand, with the rays of their last evaluation (after a full solve, the
    // rays it cast; see costs.cpp for the rest). Every such ray has an
    // end on the object, so an update that moves it casts them all again: their share of a
    // full solve's rays is a floor under any update that re-computes what a full solve would
    // (bench/update_examples.py). A link between two parts of one object belongs to none (a
    // rigid move keeps it), and an end at a cluster of several objects to no object.
    struct ObjectCost {
        int64_t point_rays = 0;
        int64_t links = 0, link_rays = 0;                  // gathering or fully occluded links
        int64_t history_links = 0, history_link_rays = 0;  // refined into others (3.4)
    };
    std::vector<ObjectCost> object_costs() const;
    // A fresh evaluation of the link src -> rcv as the solver would make it (same seed).
    Link evaluate(int src, int rcv) const;
    // Closed pockets (pockets.h): Pockets::rays of surface s as the solver casts them, and
    // each surface's escape rays at the last pocket computation.
    using PocketRay = Pockets::Ray;
    void pocket_rays(int s, int rays, uint64_t stream, std::vector<PocketRay>& hits,
                     const std::vector<Aabb>* changed = nullptr, const std::vector<PocketRay>* old = nullptr) const {
        settle_preview();
        pockets_.rays(h_, pocket_sight(), s, rays, stream, hits, changed, old);
    }
    const std::vector<std::vector<PocketRay>>& pocket_records() const { return pockets_.records(); }
    // The output points' probes of their own reach in the last final gather (FinalGather::probes).
    std::vector<double> output_probes() const { return output_.probes(); }
    const Hierarchy& hierarchy() const {
        settle_preview();
        return h_;
    }
    const Visibility& visibility() const {
        settle_preview();
        return *vis_;
    }
    const LinkStore& links() const { return links_; }
    // Per node: whether it is enclosed, and its closure factors (enclosure.h).
    const Enclosure& enclosure() const { return gathering_.enclosure(); }
    const Settings& settings() const { return settings_; }
    const SceneDesc& scene() const { return scene_; }
    double reference_radiance() const { return tolerances_.reference; }

    // --- Lights and world (solver_lights.cpp, leaf_mesh.cpp).
    // Replaces light `index` of the scene; the next update() recomputes the direct light.
    void set_light(int index, const LightDesc& light);
    // Irradiance / pi arriving at the front side at every corner (lighting only: what a white
    // surface would reflect; the surface's own emission and reflectance left out).
    std::vector<float> corner_irradiance(int object) const;
    // Irradiance / pi arriving at a leaf element's side, all links and the direct term
    // (what its reflectance multiplies; also what a black emitter absorbs).
    Rgb leaf_irradiance(int leaf) const;
    // The object's front-side leaf elements as a T-vertex free mesh, with radiance (or
    // irradiance / pi when lighting_only) per polygon.
    LeafMesh leaf_mesh(int object, bool lighting_only) const;

private:
    static constexpr int kRoundSweeps = 40;  // gathering sweeps between refinement rounds
    // What one incremental update knows (defined below, with the update's phases). The steps
    // a solve and an update share take it as an argument: null in a full solve.
    struct UpdateRun;

    // solve()'s phases (solver.cpp): the scene built, and a lit scene linked and refined
    // (true when its last closure pass and solve stand on the links as they end).
    void build_scene();
    bool link_and_refine();
    // Embree's ray offset for the scene's size (h_.scene_box, scene_diag).
    void fit_ray_epsilon();
    // The oracle (oracle.h) on the hierarchy, the settings, the direct light and the threshold
    // state: the nodes' radiance is read at each judgement, the threshold state and the
    // element count are those of now, so one is made where links are judged or split.
    Oracle oracle() const {
        return Oracle(h_, settings_, direct_light_, threshold_state(), stats_.element_nodes);
    }
    const Oracle::Threshold& threshold_state() const { return tolerances_; }
    // solver.cpp: the refinement (refinement.h) on the solver's hierarchy, links and stats with
    // the threshold state of now and the update's replay boxes (`u`), so one is made for each
    // step that links, splits or un-refines (its Context alone for the AdjustSystem, which
    // makes its own).
    Refinement::Context refinement_context(const UpdateRun* u);
    Refinement refinement(const UpdateRun* u) { return Refinement(refinement_context(u)); }
    // What the memory budget (memory_budget.h) reads of the solve as it stands now.
    MemoryView memory_view() const {
        return {settings_, scene_, h_, links_, vis_.get(), gathering_, direct_light_, output_, pockets_,
                topology_.tri_prim()};
    }
    // solver_gather.cpp: the gathering (gathering_) on the solver's hierarchy, links, direct
    // light and stats, as the oracle is made (oracle()). collect_receivers lists the leaves
    // anew and lights those lacking their direct term: whatever changes links, nodes or
    // materials must call it before the next sweep (iterate_to and compute_closure do). `u`
    // (null in a full solve): the update whose replay boxes the direct light keeps outside.
    Gathering::Context gather_context() { return {h_, links_, direct_light_, settings_, stats_}; }
    void collect_receivers(const UpdateRun* u);
    // Sweeps to `tolerance` (Gathering::iterate_to), progress from progress_from to progress_to.
    // With `keep_plan`, the leaves and the gather plan are not collected again: no link or
    // node changed since the last iterate_to.
    void iterate_to(const UpdateRun* u, double tolerance, int max_iterations, double progress_from,
                    double progress_to, bool keep_plan = false);
    // Closure factors set, then closure-driven splits, pass after pass until none splits.
    // True when its last pass split nothing (not cut by Settings::closure_refine_passes): a
    // second call on the same links would change nothing. In an update (`u`), the passes
    // keep to its closure focus.
    bool compute_closure(const UpdateRun* u);
    // What a refinement round can change of the solution's structure: links made, nodes made,
    // elements split or merged (a link judged and settled in place shows only to the round).
    struct LinkShape {
        size_t links, nodes;
        int64_t elements;
        bool operator==(const LinkShape& o) const { return links == o.links && nodes == o.nodes && elements == o.elements; }
    };
    LinkShape link_shape() const { return {links_.size(), h_.nodes.size(), stats_.element_nodes}; }
    // adjust.cpp
    // move_object's matrix as a placement in the internal frame (InputError when not rigid).
    Rigid pose_of(int object, const std::array<double, 16>& m) const;
    // What an update changed in the geometry (moves here, additions and removals by
    // Topology::apply), for the AdjustSystem (adjust_system.h).
    using Change = AdjustSystem::Change;
    // What one incremental update knows, handed from phase to phase (update()).
    struct UpdateRun {
        bool topology = false;            // objects added or removed
        bool materials_changed = false;   // emission or reflectance changed (for the output)
        int64_t links_before = 0;         // links made from here on are this update's
        std::vector<float> before;        // radiances before the update
        std::vector<float> judged_before; // ... as the oracle judges (judging_radiance)
        std::vector<int> recheck_history; // history links whose view the moves changed
        bool rejudge_all = false;         // the oracle's threshold moved: judge every link
        std::vector<Aabb> now_boxes;      // the moved objects' new boxes
        std::vector<char> moved_objects;  // per object: moved
        // Moves only (no addition or removal): the moved objects' old and new boxes, outside
        // which every ray's outcome is as recorded, so links re-evaluate by replay.
        bool replaying = false;
        std::vector<Aabb> replay_clips;
        // Moves only: away from these boxes a closure pass splits only links made since
        // links_before (empty: no focus).
        std::vector<Aabb> closure_focus;
    };
    // The boxes outside which a recorded ray keeps its outcome, a shadow ray's or a link's,
    // in the update `u` (null: nothing replays, as in a full solve).
    static const std::vector<Aabb>* replay_boxes(const UpdateRun* u) {
        return u && u->replaying ? &u->replay_clips : nullptr;
    }
    // The update's phases, in order; update_materials and update_adjust return false when
    // they solved in full instead.
    void update_begin(UpdateRun& u);
    bool update_materials(Control* control);  // emission and reflectance changes
    bool update_adjust(UpdateRun& u, Control* control);  // place the moved objects, AdjustSystem
    void update_history(UpdateRun& u);         // un-refine history links, lights
    void update_resolve(const UpdateRun& u);   // closure, gathering, un-refinement, refine rounds, prune
    // update_resolve's steps. History links taken back (3.4) where their sender's light changed
    // since the update began (every sender after a new threshold); returns those senders.
    std::vector<char> update_unrefine(const UpdateRun& u);
    // How the refine rounds ended: whether the last round solved to the tolerance on the links
    // as they end (the round cap reached), and whether the last closure pass and solve stand
    // on the links and leaves as they are.
    struct RoundsEnd {
        bool solved_final_links = false;
        bool closure_current = false;
    };
    // Rounds of judging the links against the new light (those update_judged picks, starting
    // from the senders in `moved_light`), each followed by a closure pass and a solve to
    // `loose`, until a round splits nothing or the round cap.
    RoundsEnd update_refine_rounds(const UpdateRun& u, std::vector<char> moved_light, double loose);
    // A refine round's links to judge (new since `judged_from`, flagged, or from a sender whose
    // light moved) and, among them, the settled ones whose sender's first bounce grew.
    void update_judged(const UpdateRun& u, int round, int64_t judged_from, const std::vector<char>& moved_light,
                       std::vector<int>& ids, std::vector<int>& unsettle) const;
    void update_output(const UpdateRun& u);    // final gather, stats
    // A full solve in place of an update (pending moves become placements); `why` goes into
    // the stats, with its warning.
    void solve_instead(Control* control, UpdateFallback why);
    // The AdjustSystem (adjust_system.h) for `ch` on the solver's hierarchy, links and stats,
    // with the threshold state of now and u's replay boxes: made once the update knows them.
    AdjustSystem adjust_system(const Change& ch, const UpdateRun& u);
    // preview.cpp: the objects of a drag's step placed away from where the solution has them,
    // with their placements, validated as move_object validates them.
    std::vector<std::pair<int, Rigid>> preview_placements(const std::map<int, std::array<double, 16>>& moves) const;
    // Puts back the placement the last drag step kept (Embree's and the hierarchy's), if any:
    // whatever is not the next step of that drag reads or changes the solution's placement.
    void settle_preview() const;
    // Pending removals and additions applied (Topology::apply) to the hierarchy, Embree and
    // `ch`, then the tolerances and the direct light that follow from them.
    void apply_topology(Change& ch);
    void refit_tolerances();
    void set_material(int object, const std::vector<Rgb>& values, bool emission);
    // Nodes whose radiance (or its range below them) moved enough since `snap` to change an
    // oracle judgement of a link they send through.
    std::vector<char> changed_senders(const std::vector<float>& snap) const;
    std::vector<float> snapshot() const;
    // Per node: the radiance a full solve settles links on (lit scene: first_bounce; else
    // the largest channel of `snap`).
    std::vector<float> judging_radiance(const std::vector<float>& snap) const;
    void prune_elements();
    // solver_lights.cpp: the steps that light, split and coarsen elements through
    // direct_light_ (the hierarchy and the element count stay the solver's), and what its
    // shadow rays are cast into (valid while vis_ is). `u`: the update they run in (its
    // replay boxes, for the leaves they light again), null in a full solve.
    DirectLight::Sight light_sight() const { return {scene_, *vis_, settings_}; }
    void light_initial();                      // before the first linking: split and light
    void light_update(const UpdateRun& u);     // before an update's solve: invalidate, coarsen, split again
    bool light_refine(const UpdateRun* u);     // split leaves whose direct light varies (DirectLight::refine)
    bool light_coarsen(const UpdateRun* u);    // drop the children of light splits no longer needed
    // Runs `judge_links` with every node's radiance set to DirectLight::first_bounce's (then
    // restored); `only`: per node, the leaves to set (the rest keep theirs).
    void at_first_bounce(const std::function<void()>& judge_links, const std::vector<char>* only = nullptr);
    DirectLight direct_light_;  // direct_light.h
    // output.cpp: the final gather at every output point (the "output" phase of a solve or an
    // update), progress from `from` to `to`.
    // With `moves` (an update that moved objects or changed materials only): FinalGather::retrace.
    void final_gather(double from, double to, const FinalGather::Moves* moves = nullptr);
    FinalGather output_;
    // solver.cpp
    void compute_reference();
    // What the pockets' escape rays are cast into (valid while vis_ is).
    Pockets::Sight pocket_sight() const { return {*vis_, topology_.tri_prim(), settings_}; }
    void check_cancel() const;
    void set_progress(double f) const;
    // The stats read off the parts at a run's end (report.h), the warnings its result deserves
    // among them.
    void compute_stats();
    // Ends a timed phase of the run under way (RunClock::lap on stats_, the rays of vis_).
    void lap(const char* phase);

    SceneDesc scene_;
    Settings settings_;
    Hierarchy h_;
    std::unique_ptr<Visibility> vis_;
    LinkStore links_;              // every link, with its history (link_store.h)
    Gathering gathering_;          // the sweeps and their plan (gathering.h)
    MemoryBudget memory_;          // the memory cap and what the solve holds (memory_budget.h)
    Stats stats_;
    // The run under way, a solve() or an update(), made on its stack (null between runs): its
    // Control (cancellation, progress), which check_cancel and set_progress read, and its
    // clock, which lap reads. Made, it takes `slot` (run_); at its end it puts back the run it
    // interrupted (a solve in place of an update), whether its run returns or throws
    // (Cancelled): no Control or clock outlives its run.
    class Run {
    public:
        Run(Run*& slot, Control* control, int64_t rays) : control(control), clock(rays), slot_(slot), outer_(slot) {
            slot_ = this;
        }
        ~Run() { slot_ = outer_; }
        Run(const Run&) = delete;
        Run& operator=(const Run&) = delete;

        Control* const control;
        RunClock clock;

    private:
        Run*& slot_;
        Run* outer_;
    };
    Run* run_ = nullptr;
    // The oracle's threshold state: the reference radiance (compute_reference), the
    // scene-wide threshold made from it, the element area floor (refit_tolerances), and
    // whether the nodes' radiance L estimates the light yet (false from a solve's start until
    // its first gathering: only then may a link's threshold follow its receiver's light). The
    // solution's: set by a solve and kept by every update after it.
    Oracle::Threshold tolerances_;
    bool solved_ = false;
    PendingEdits edits_;  // moves and materials since the last update, and each object's placement
    Topology topology_;   // objects added and removed, and each object's triangles in Embree (topology.h)
    Pockets pockets_;  // closed pockets and the escape rays that found them
    // The live drag's placement (live_drag.h): between the steps of one drag the hierarchy
    // and Embree hold the last step's placement, put back by settle_preview, which const
    // readers call too (the placement a drag holds is not the solution's state).
    mutable LiveDrag drag_;
};

}  // namespace radiosity
