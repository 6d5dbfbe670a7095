#include "radiosity/solver.h"

#include <chrono>
#include <cmath>

#include "report.h"

namespace radiosity {

namespace {
using Clock = RunClock::Clock;
}  // namespace

Solver::Solver(SceneDesc scene, Settings settings)
    : scene_(std::move(scene)), settings_(settings), memory_(settings_.max_memory_mb) {
    settings_.validate();
}

void Solver::check_cancel() const {
    if (run_ && run_->control && run_->control->cancel.load(std::memory_order_relaxed)) throw Cancelled();
}

void Solver::set_progress(double f) const {
    if (run_ && run_->control) run_->control->fraction.store(f, std::memory_order_relaxed);
}

void Solver::solve(Control* control) {
    solved_ = false;
    tolerances_.light_known = false;
    settle_preview();
    drag_.forget();  // (a drag's memory, made again at the next drag)
    Run run(run_, control, 0);  // a new Visibility counts from 0
    stats_ = Stats{};
    links_.clear();
    direct_light_.clear();   // the hierarchy is rebuilt
    gathering_.enclosure().clear();
    topology_.commit(scene_, edits_);  // objects removed since are left out
    build_scene();
    stats_.seconds_build = run.clock.seconds();
    lap("build");
    set_progress(0.05);

    edits_.take_moves();      // not applied: a move reaches a full solve as a placement (solve_instead)
    edits_.take_materials();  // in scene_ already
    output_.clear();  // output.cpp: traced at the end, when there is light
    if (tolerances_.reference <= 0) {
        stats_.no_emitters = true;
        stats_.warnings.push_back("the scene has no emitter: every radiance is 0");
    } else {
        const auto t1 = Clock::now();
        const bool closure_current = link_and_refine();
        stats_.seconds_link = RunClock::seconds_since(t1);
        const auto t2 = Clock::now();
        if (!closure_current) {
            compute_closure(nullptr);
            lap("closure");
        }
        stats_.iteration_capped = false;
        iterate_to(nullptr, settings_.tolerance, settings_.max_iterations, 0.8, 0.9, closure_current);
        lap("gather");
        final_gather(0.9, 1.0);  // output.cpp
        lap("output");
        stats_.seconds_solve = RunClock::seconds_since(t2);
    }
    if (stats_.element_nodes >= settings_.max_elements) stats_.capped = true;
    compute_stats();
    lap("stats");
    stats_.seconds_total = run.clock.seconds();
    set_progress(1.0);
    solved_ = true;
}

// A full solve's first phase: the hierarchy and Embree's scene from scene_, with the
// placements of earlier moves, then the pockets and the reference radiance.
void Solver::build_scene() {
    h_.build(scene_, settings_.use_clustering);
    vis_ = std::make_unique<Visibility>();
    fit_ray_epsilon();
    std::vector<std::vector<int>> prims_of(scene_.objects().size());
    for (size_t pi = 0; pi < h_.prims.size(); ++pi)
        if (h_.prims[pi].object >= 0) prims_of[size_t(h_.prims[pi].object)].push_back(int(pi));  // -1: skipped
    topology_.build_geometry(scene_, h_, *vis_, prims_of);
    stats_.element_nodes = int64_t(h_.surfaces.size());
    tolerances_.min_area = settings_.min_area_fraction * h_.scene_diag * h_.scene_diag;

    // Placements from earlier moves survive a full re-solve.
    edits_.fit_poses(scene_.objects().size());
    const std::vector<Rigid>& poses = edits_.poses();
    std::vector<std::pair<int, Rigid>> placed;
    std::vector<std::vector<int>> own;
    for (size_t o = 0; o < poses.size(); ++o)
        if (!poses[o].identity()) {
            placed.emplace_back(int(o), poses[o]);
            own.push_back(prims_of[o]);
        }
    h_.place_objects(placed, true, &own, settings_.threads);
    for (const auto& [o, p] : placed) vis_->set_object_transform(o, p);
    vis_->commit();
    pockets_.compute(h_, pocket_sight());
    memory_.measure_tables(memory_view());
    compute_reference();
}

// Ray offsets relative to the scene size (scale invariance), but never below what float
// coordinates far from the origin can resolve.
void Solver::fit_ray_epsilon() {
    double mag = 0;
    for (int k = 0; k < 3; ++k)
        mag = std::max({mag, std::fabs(h_.scene_box.lo[k]), std::fabs(h_.scene_box.hi[k])});
    vis_->set_epsilon(std::max(1e-6 * h_.scene_diag, 4e-7 * mag));
}

// A lit scene's linking: first-bounce light, links from the root's self-link down, then
// rounds of gathering and refinement until the oracle splits nothing (or the round cap).
bool Solver::link_and_refine() {
    light_initial();  // solver_lights.cpp: lit surfaces get their first-bounce radiance before linking
    h_.index_emitters();  // can_split: small emitting clusters still split
    memory_.forecast_output(memory_view());  // refinement leaves room for the output (follow_forecast)
    refinement(nullptr).link_from({{h_.root, h_.root, -1}});
    lap("link");
    set_progress(0.2);
    // Refine against the evolving solution (BF refinement): light arriving from
    // reflectors becomes known only after some gathering; a few sweeps per round are
    // enough for the oracle, the last solve converges.
    const double loose = std::max(settings_.tolerance, 1e-3);
    const int round_sweeps = std::min(settings_.max_iterations, kRoundSweeps);
    for (int round = 0; round < settings_.max_refine_rounds; ++round) {
        check_cancel();
        const bool closure_settled = compute_closure(nullptr);
        lap("closure");
        iterate_to(nullptr, loose, round_sweeps, 0.2 + 0.6 * round / settings_.max_refine_rounds,
                   0.2 + 0.6 * (round + 0.5) / settings_.max_refine_rounds);
        lap("gather");
        tolerances_.light_known = true;
        ++stats_.refine_rounds;
        const LinkShape was = link_shape();
        bool touched = false;
        const bool lights_split = light_refine(nullptr);  // solver_lights.cpp: where direct light varies
        const bool more = refinement(nullptr).refine_active(&touched) || lights_split;
        lap("refine");
        // Nothing judged, split or merged since this round's closure pass and solve: they stand.
        if (!more) return closure_settled && !touched && link_shape() == was;
    }
    return false;
}

void Solver::lap(const char* phase) {
    if (run_) run_->clock.lap(stats_, phase, vis_ ? int64_t(vis_->rays()) : 0);
}

Refinement::Context Solver::refinement_context(const UpdateRun* u) {
    return {h_, links_, *vis_, direct_light_, settings_, stats_, threshold_state(), replay_boxes(u),
            [this] {
                check_cancel();
                memory_.follow_forecast(memory_view());
            },
            [this](size_t more_links, size_t more_nodes) { return memory_.over(memory_view(), more_links, more_nodes); },
            [this](const std::function<void()>& judge) { at_first_bounce(judge); }};
}

Link Solver::evaluate(int src, int rcv) const {
    settle_preview();
    // Every ray cast: no update runs, so nothing replays.
    return LinkEvaluator{h_, *vis_, settings_, oracle(), nullptr}.evaluate(src, rcv);
}

void Solver::compute_reference() {
    // Reference radiance for the relative threshold: the mean radiance a closed scene with
    // this emission and mean reflectance would reach.
    const Hierarchy::SurfaceTotals t = h_.surface_totals();
    const double rho_mean = t.area > 0 ? std::min(t.reflectance / t.area, 0.95) : 0.0;
    // The Blender lights and world, added to the emitting surfaces.
    const double ae = t.emission + DirectLight::power(scene_, h_, t.area) * std::max(rho_mean, 0.1);
    tolerances_.reference = t.area > 0 ? ae / t.area / (1.0 - rho_mean) : 0.0;
    tolerances_.threshold = settings_.error_threshold * tolerances_.reference;
}

void Solver::compute_stats() {
    Stats& s = stats_;
    const DirectLight::ContactWork contacts = direct_light_.take_contact_work();
    s.contact_surfaces = contacts.surfaces;
    s.seconds_contacts = contacts.seconds;
    s.input_surfaces = int64_t(scene_.polygon_count());
    const double held = memory_.estimate(memory_view());
    add_result_warnings(h_, settings_, held, memory_.limit(), s);
    s.memory_bytes = int64_t(held);
    s.primitives = 0;
    for (const Primitive& p : h_.prims) s.primitives += p.object >= 0;  // removed objects' are -1
    s.skipped_polygons = int64_t(h_.skipped_polygons);
    s.objects = 0;
    for (size_t o = 0; o < scene_.objects().size(); ++o) s.objects += !removed(int(o));
    s.clusters = 0;
    for (const Node& n : h_.nodes) s.clusters += n.is_cluster() && !n.dead;
    count_links(h_, links_, s);
    s.elements = lit_elements(h_, links_, direct_light_);
    s.closed_pockets = pockets_.closed_pockets();
    s.pocket_surfaces = pockets_.pocket_surfaces();
    s.rays = vis_ ? int64_t(vis_->rays()) : 0;
}

}  // namespace radiosity
