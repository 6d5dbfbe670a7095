// Dynamic environments (paper 3.2-3.4): the edits recorded between updates (rigid moves,
// emission and reflectance; objects added and removed through Topology, topology.h), and
// update()'s pipeline of phases: the moved objects placed, the AdjustSystem (adjust_system.h)
// run on the change, history links and lights, the warm-started re-solve with un-refinement,
// and the output.
#include <algorithm>
#include <cmath>
#include <functional>

#include "radiosity/parallel.h"
#include "radiosity/solver.h"
#include "radiosity/transfer.h"
#include "report.h"

namespace radiosity {

namespace {
// The warning an update that solved in full adds for people (Stats::update_fallback is the
// code programs read); none for a scene without light, whose own warning says so.
const char* fallback_warning(UpdateFallback why) {
    switch (why) {
        case UpdateFallback::scene_size:
            return "objects added or removed changed the scene's size: solved in full (the scene's frame changes)";
        case UpdateFallback::pocket_moved: return "a move changed a closed pocket: solved in full";
        case UpdateFallback::pocket_added_removed:
            return "an object added or removed changed a closed pocket: solved in full";
        case UpdateFallback::none:
        case UpdateFallback::no_light: break;
    }
    return nullptr;
}
}  // namespace

void Solver::move_object(int object, const std::array<double, 16>& m) {
    settle_preview();
    if (!solved()) throw std::logic_error("move_object: solve the scene first");
    topology_.check_live(scene_, object, "move_object");
    edits_.record_move(object, pose_of(object, m));
}

int Solver::add_cluster(const std::string& name, int parent) {
    settle_preview();
    return topology_.add_cluster(scene_, name, parent);
}

int Solver::add_object(ObjectDesc object) {
    settle_preview();
    return topology_.add_object(scene_, std::move(object), solved());
}

void Solver::remove_object(int object) {
    settle_preview();
    topology_.remove_object(scene_, edits_, object, solved());
}

Rigid Solver::pose_of(int object, const std::array<double, 16>& m) const {
    return Rigid::from_world(m, h_.origin, h_.unit, "object '" + scene_.objects()[object].name + "'");
}

void Solver::set_material(int object, const std::vector<Rgb>& values, bool emission) {
    settle_preview();
    topology_.check_live(scene_, object, emission ? "set_emission" : "set_reflectance");
    ObjectDesc& o = scene_.objects_mut()[object];
    check_polygon_materials(o, values, emission);
    auto& dst = emission ? o.emission : o.reflectance;
    for (size_t f = 0; f < dst.size(); ++f) dst[f] = values.size() == 1 ? values[0] : values[f];
    edits_.record_materials();
}

void Solver::set_emission(int object, const std::vector<Rgb>& v) { set_material(object, v, true); }
void Solver::set_corner_materials(int object, std::vector<Rgb> reflectance, std::vector<Rgb> emission) {
    settle_preview();
    topology_.check_live(scene_, object, "set_corner_materials");
    ObjectDesc& o = scene_.objects_mut()[object];
    check_corner_materials(o, reflectance, emission);
    o.corner_reflectance = std::move(reflectance);
    o.corner_emission = std::move(emission);
}
void Solver::set_reflectance(int object, const std::vector<Rgb>& v) { set_material(object, v, false); }
void Solver::set_texture_pieces(int object, std::vector<TexturePiece> pieces, bool emit) {
    settle_preview();
    topology_.check_live(scene_, object, "set_texture_pieces");
    ObjectDesc& o = scene_.objects_mut()[object];
    if (pieces.empty() && o.pieces.empty()) return;
    check_pieces(o, pieces);
    o.pieces = std::move(pieces);
    o.pieces_emit = emit && !o.pieces.empty();
    std::vector<int> ids;
    for (size_t p = 0; p < h_.prims.size(); ++p)
        if (h_.prims[p].object == object) ids.push_back(int(p));
    h_.bind_pieces(o, ids);
    edits_.record_materials();
}

// Bottom-up clean-up of elements no link refers to any more (3.4): memory for links
// returns at once; element slots are retired (Hierarchy::retire_below), not reused.
void Solver::prune_elements() {
    std::vector<int> refs(h_.nodes.size(), 0);
    for (const Link& l : links_)
        if (!l.dead) ++refs[l.src], ++refs[l.rcv];
    direct_light_.keep(h_, light_sight(), tolerances_.threshold, refs);  // children the direct light needs
    std::function<bool(int)> prune = [&](int id) -> bool {  // true: the subtree has no reference
        Node& n = h_.nodes[id];
        bool empty = refs[id] == 0;
        bool kids_empty = true;
        for (int c : n.children) kids_empty &= prune(c);
        if (!n.children.empty() && kids_empty) {
            bool all_leaves = true;
            for (int c : h_.nodes[id].children) all_leaves &= h_.nodes[c].children.empty();
            if (all_leaves) stats_.element_nodes -= h_.retire_below(id);
        }
        return empty && h_.nodes[id].children.empty();
    };
    for (const Surface& s : h_.surfaces)
        if (!h_.nodes[s.root].dead) prune(s.root);  // removed objects' nodes are gone already
}

// Per node: radiance and its range below (max - min), 6 floats.
std::vector<float> Solver::snapshot() const {
    std::vector<float> v(h_.nodes.size() * 6);
    for (size_t i = 0; i < h_.nodes.size(); ++i) {
        const Node& n = h_.nodes[i];
        for (int k = 0; k < 3; ++k) {
            v[6 * i + k] = float(n.L[k]);
            v[6 * i + 3 + k] = float(n.Lmax[k] - n.Lmin[k]);
        }
    }
    return v;
}

std::vector<char> Solver::changed_senders(const std::vector<float>& snap) const {
    // A judgement compares errors proportional to the sender's radiance (and its range) with
    // the threshold: a relative change of a few percent can tip it, a change of a sender too
    // dim to matter cannot. Nodes made since the snapshot count as changed.
    const double floor = 0.01 * tolerances_.threshold, rel = 0.02;
    std::vector<char> d(h_.nodes.size(), 1);
    const size_t known = std::min(h_.nodes.size(), snap.size() / 6);
    parallel_for(known, settings_.threads, [&](size_t i) {
        const Node& n = h_.nodes[i];
        bool c = false;
        for (int k = 0; k < 3 && !c; ++k) {
            const double L0 = snap[6 * i + k], R0 = snap[6 * i + 3 + k];
            const double L1 = n.L[k], R1 = n.Lmax[k] - n.Lmin[k];
            c = (std::fabs(L1 - L0) > rel * L0 && std::max(L0, L1) > floor) ||
                (std::fabs(R1 - R0) > rel * R0 && std::max(R0, R1) > floor);
        }
        d[i] = c;
    }, 4096);
    return d;
}

std::vector<float> Solver::judging_radiance(const std::vector<float>& snap) const {
    // Per node, the radiance a full solve settles links (3.5) on: in a lit scene the lamps'
    // first bounce, which its first linking judges by (see at_first_bounce); otherwise the
    // gathered radiance of its refinement rounds (`snap`, from snapshot()).
    if (!scene_.lights().empty()) return direct_light_.first_bounce(h_);
    std::vector<float> v(snap.size() / 6);
    for (size_t i = 0; i < v.size(); ++i) v[i] = std::max({snap[6 * i], snap[6 * i + 1], snap[6 * i + 2]});
    return v;
}

void Solver::update(Control* control) {
    // The pipeline of an incremental update; each phase is a function below. A phase that
    // finds the update cannot be incremental solves in full instead and returns false.
    settle_preview();
    if (!solved()) {
        solve(control);
        return;
    }
    drag_.forget();  // (a drag's memory, made again at the next drag)
    UpdateRun u;
    u.topology = topology_.pending();
    u.materials_changed = edits_.materials();
    stats_.update_fallback = UpdateFallback::none;  // (until a phase below solves in full)
    if (!edits_.any() && !u.topology) {
        stats_.mode_incremental = true;
        stats_.seconds_adjust = 0;
        return;
    }
    if (topology_.outgrows_frame(scene_, h_)) {
        solve_instead(control, UpdateFallback::scene_size);
        return;
    }
    Run run(run_, control, int64_t(vis_->rays()));
    solved_ = false;  // a cancel leaves the kept solution inconsistent: the caller re-solves
    // What this update knows lives in `u` for its phases only, handed to each step that needs it.
    update_begin(u);
    if (!update_materials(control)) return;
    if (!edits_.moves().empty() || u.topology)
        if (!update_adjust(u, control)) return;
    update_history(u);
    update_resolve(u);
    update_output(u);
}

void Solver::solve_instead(Control* control, UpdateFallback why) {
    // A full solve builds from scene_: additions are in, removals are committed by solve(),
    // moves become placements.
    edits_.fit_poses(scene_.objects().size());  // a move can name an object added since
    for (const auto& [obj, pose] : edits_.take_moves()) edits_.place(obj, pose);
    solve(control);
    stats_.update_fallback = why;
    if (const char* text = fallback_warning(why)) stats_.warnings.push_back(text);
}

void Solver::update_begin(UpdateRun& u) {
    stats_.phases.clear();
    stats_.phase_rays.clear();
    stats_.warnings.clear();  // this update's own (compute_stats adds the result's at the end)
    Stats& s = stats_;
    s.env_env_links_tested = s.env_env_links_rejected = s.env_env_links_recomputed = 0;
    s.history_links_recomputed = s.history_links_stale = 0;
    s.env_env_links_rays_clear = 0;
    s.obj_env_links_removed = s.links_created = s.history_reactivated = 0;
    s.objects_added = s.objects_removed = s.links_removed = 0;
    s.iterations = 0;
    s.link_sweeps = s.gather_plans = 0;
    s.seconds_sweeps = s.seconds_gather_plan = 0;
    s.refine_rounds = 0;
    s.iteration_capped = false;
    direct_light_.take_contact_work();  // (this update's own from here)
    u.links_before = int64_t(links_.size());
    u.before = snapshot();
    u.judged_before = judging_radiance(u.before);
}

bool Solver::update_materials(Control* control) {
    if (edits_.take_materials()) {
        h_.apply_materials(scene_);
        compute_reference();  // the threshold follows the new emission and reflectance
    }
    if (tolerances_.reference <= 0 || stats_.no_emitters) {
        // Dark now: a zero reference makes the oracle's threshold 0, and the update would
        // refine every link to the caps. Dark before: solve() made no links,
        // so there is nothing to update. solve() handles both.
        solve_instead(control, UpdateFallback::no_light);
        return false;
    }
    h_.index_emitters();  // can_split: small emitting clusters still split (materials may have changed)
    return true;
}

AdjustSystem Solver::adjust_system(const Change& ch, const UpdateRun& u) {
    return AdjustSystem({h_, links_, gathering_.enclosure(), settings_, stats_, ch, refinement_context(&u),
                         [this](const std::function<void()>& judge, const std::vector<char>* only) {
                             at_first_bounce(judge, only);
                         },
                         [this](const char* phase) { lap(phase); }});
}

void Solver::apply_topology(Change& ch) {
    topology_.apply({scene_, h_, *vis_, links_, edits_, settings_, stats_}, ch);
    refit_tolerances();
    // The direct light of every leaf may have a new shadow (or lost one), as after a move;
    // contacts refer to surfaces that may be gone.
    direct_light_.relight();
    direct_light_.forget_contacts();
}

// The scene's size changed (Topology::outgrows_frame allows up to 2x): the tolerances a fresh
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
    tolerances_.min_area = settings_.min_area_fraction * h_.scene_diag * h_.scene_diag;
    fit_ray_epsilon();
}

bool Solver::update_adjust(UpdateRun& u, Control* control) {
    Change ch;
    ch.moves = edits_.take_moves();
    ch.inX.assign(h_.nodes.size(), 0);
    const size_t known_surfaces = h_.surfaces.size();
    if (u.topology) apply_topology(ch);
    // Geometry and Embree instances of moved objects.
    ch.moved.assign(scene_.objects().size(), 0);
    std::vector<std::pair<int, Rigid>> placed(ch.moves.begin(), ch.moves.end());
    std::vector<std::vector<int>> prims;
    std::vector<Aabb> was;
    for (const auto& [obj, pose] : placed)
        was.push_back(h_.object_box(obj, &prims.emplace_back(topology_.own_prims(obj))));
    h_.place_objects(placed, true, &prims, settings_.threads);
    for (size_t j = 0; j < placed.size(); ++j) {
        const auto& [obj, pose] = placed[j];
        edits_.place(obj, pose);
        vis_->set_object_transform(obj, pose);
        ch.clips.push_back(was[j]);
        ch.clips.push_back(h_.object_box(obj, &prims[j]));
        ch.now.push_back(ch.clips.back());
        ch.moved[obj] = 1;
    }
    vis_->commit();
    for (Aabb& c : ch.clips) c = c.grown(1e-5);  // ray ends are lifted off surfaces: a hair of margin
    // Which polygons lie on which follows the placements, near the moved objects alone (the
    // output's contact test needs it with or without lights).
    direct_light_.moved_contacts(ch.clips);
    lap("place");
    // Moves only: outside the moved objects' old and new boxes every ray meets what it met.
    // An addition or removal re-orders the surface table the cluster samplers draw from
    // (Hierarchy::surface_order, area_prefix), which can change a link's rays themselves.
    u.replaying = settings_.replay_rays && !u.topology;
    u.replay_clips = ch.clips;
    // Closed pockets (pockets.cpp) decide which links may exist at all: when a move, an
    // addition or a removal changes which pocket a surface that stays is in, or puts new
    // surfaces into a closed pocket, solve in full (rare: an object put into or taken out
    // of a closed crate).
    if (!pockets_.reseal(h_, pocket_sight(), known_surfaces, u.replaying ? &ch.clips : nullptr, &ch.moved)) {
        solve_instead(control, u.topology ? UpdateFallback::pocket_added_removed : UpdateFallback::pocket_moved);
        return false;
    }
    memory_.measure_tables(memory_view());
    lap("pockets");
    if (u.topology) {
        // Area and emission changed: the reference radiance, and with it the oracle's
        // threshold. Beyond the tolerance changed_senders() uses, every link is judged again.
        const double old_threshold = tolerances_.threshold;
        compute_reference();
        if (tolerances_.reference <= 0) {
            solve_instead(control, UpdateFallback::no_light);
            return false;
        }
        u.rejudge_all = std::fabs(tolerances_.threshold - old_threshold) > 0.02 * old_threshold;
        lap("topology");
    }
    // X: the moved objects' nodes and the clusters above them (their geometry changed).
    AdjustSystem::mark_moved(h_, ch);
    u.recheck_history = adjust_system(ch, u).run();
    u.now_boxes = ch.now;
    u.moved_objects = ch.moved;
    // The closure passes of this update split, away from the moved boxes, only the links
    // made since (the moved objects' new links change the sums of leaves far off): the
    // links that were there passed the full solve's closure passes as they are
    // (docs/decisions.md, "An update's closure passes split only links made since").
    if (!u.topology) u.closure_focus = ch.clips;
    return true;
}

void Solver::update_history(UpdateRun& u) {
    stats_.links_created = int64_t(links_.size()) - u.links_before;
    // History links whose view changed: coarsen back where the old shadow is gone.
    refinement(&u).recheck_history(u.recheck_history);
    stats_.seconds_adjust = run_->clock.seconds();
    lap("history");
    light_update(u);  // solver_lights.cpp: drop light splits the new direct light does not need
    lap("lights");
}

void Solver::update_resolve(const UpdateRun& u) {
    // Warm-started re-solve: the previous radiances are the starting point. Only links the
    // update touched, or whose sender's light changed enough to tip the oracle, are judged
    // again; a full solve's refine rounds judge every link.
    // The solves the oracle judges converge as far as a full solve's refine rounds do
    // (`loose`, solver.cpp); only the last one to the tolerance (docs/decisions.md, "An
    // update's closure passes split only links made since").
    const double loose = std::max(settings_.tolerance, 1e-3);
    // What a move buried (the floor under the box's new place) keeps the radiance solved when
    // it was open until the first gather. Taken for light, it would split the links into the
    // box's inside, which the floor sees through the contact (two-sided faces), down to the
    // area limit, and every closure pass again, since those leaves' sums stay above 1 however
    // deep they go. A full solve judges them on the first bounce, where a buried floor is dark:
    // so do the AdjustSystem's relink and this closure pass, for the buried leaves only; the
    // rest keeps the solved radiance, nearly right after a small move (docs/decisions.md,
    // "Links an update judges on a buried surface").
    AdjustSystem::judge_where_buried(
        h_, u.now_boxes, u.moved_objects,
        [this](const std::function<void()>& judge, const std::vector<char>* only) { at_first_bounce(judge, only); },
        [&] { compute_closure(&u); });
    lap("closure");
    iterate_to(&u, loose, settings_.max_iterations, 0.3, 0.6);
    lap("gather");
    std::vector<char> moved_light = update_unrefine(u);
    const RoundsEnd end = update_refine_rounds(u, std::move(moved_light), loose);
    if (!end.solved_final_links) {
        // Warm: a handful of sweeps when nothing changed since the last solve. When no link or
        // leaf changed since the last closure pass, that pass stands and so does the plan.
        if (!end.closure_current) {
            compute_closure(&u);
            lap("closure");
        }
        iterate_to(&u, settings_.tolerance, settings_.max_iterations, 0.9, 0.95, end.closure_current);
        lap("gather");
    }
    prune_elements();
    lap("prune");
}

std::vector<char> Solver::update_unrefine(const UpdateRun& u) {
    std::vector<char> moved_light = changed_senders(u.before);
    // A new threshold (objects added or removed) can tip any judgement.
    if (u.rejudge_all) std::fill(moved_light.begin(), moved_light.end(), 1);
    refinement(&u).unrefine_pass(&moved_light, !scene_.lights().empty());  // less light somewhere (3.4)
    lap("unrefine");
    return moved_light;
}

Solver::RoundsEnd Solver::update_refine_rounds(const UpdateRun& u, std::vector<char> moved_light, double loose) {
    // The closure factors and the converged radiances belong to the links as they were before
    // un-refinement and these rounds: the last solve must see the final links. At the start
    // neither the last closure pass nor the last solve stands (the un-refinement changed the
    // links since).
    RoundsEnd end;
    int64_t judged_from = u.links_before;  // links made since are new: judge them all
    for (int round = 0; round < settings_.max_refine_rounds; ++round) {
        check_cancel();
        ++stats_.refine_rounds;
        const LinkShape was = link_shape();
        std::vector<int> ids, unsettle;
        update_judged(u, round, judged_from, moved_light, ids, unsettle);
        refinement(&u).reopen_settled(unsettle);
        for (Link& l : links_) l.rejudge = false;
        const std::vector<float> snap = snapshot();
        judged_from = int64_t(links_.size());
        const bool lit = light_refine(&u);  // solver_lights.cpp: where direct light varies
        bool more = lit, touched = false;
        // A lit scene's first judgement on the radiance a full solve's first linking sees.
        if (round == 0 && !scene_.lights().empty())
            at_first_bounce([&] { more = refinement(&u).refine_links(ids, &touched) || more; });
        else
            more = refinement(&u).refine_links(ids, &touched) || more;
        lap("refine");
        end.closure_current = end.closure_current && !touched && unsettle.empty() && link_shape() == was;
        if (!more) break;
        end.closure_current = compute_closure(&u);
        lap("closure");
        end.solved_final_links = round + 1 == settings_.max_refine_rounds;
        iterate_to(&u, end.solved_final_links ? settings_.tolerance : loose, settings_.max_iterations, 0.6, 0.9);
        lap("gather");
        moved_light = changed_senders(snap);
    }
    return end;
}

void Solver::update_judged(const UpdateRun& u, int round, int64_t judged_from, const std::vector<char>& moved_light,
                           std::vector<int>& ids, std::vector<int>& unsettle) const {
    const std::vector<float> judged_now = round == 0 ? judging_radiance(snapshot()) : std::vector<float>();
    const double floor = 0.01 * tolerances_.threshold;
    for (size_t i = 0; i < links_.size(); ++i) {
        const Link& l = links_[i];
        if (!l.active || !(int64_t(i) >= judged_from || l.rejudge || moved_light[l.src])) continue;
        ids.push_back(int(i));
        const size_t p = size_t(l.src);
        if (l.settled && p < u.judged_before.size() && p < judged_now.size() &&
            judged_now[p] > 1.02 * u.judged_before[p] && judged_now[p] > floor)
            unsettle.push_back(int(i));
    }
}

void Solver::update_output(const UpdateRun& u) {
    Stats& s = stats_;
    // output.cpp: after moves alone (or material changes) the output keeps what no moved box
    // can change; an addition or removal re-orders what the cluster samplers draw: anew.
    if (!u.topology) {
        FinalGather::Moves mv;
        mv.moved = u.moved_objects.empty() ? std::vector<char>(scene_.objects().size(), 0) : u.moved_objects;
        mv.clips = u.replay_clips;
        if (u.moved_objects.empty()) mv.clips.clear();
        mv.materials_changed = u.materials_changed;
        final_gather(0.95, 1.0, &mv);
    } else {
        final_gather(0.95, 1.0);
    }
    lap("output");
    // A record stays true only while every change of geometry is replayed into it: after an
    // addition or removal (surface table re-ordered, see above) none is trusted.
    for (Link& l : links_)
        // A stale link's record is of the geometry before this update's moves: a later
        // update's replay (whose boxes are its own moves') would take outcomes it changed.
        if (u.topology || l.stale) l.ray_count = -1;
    compute_stats();
    lap("stats");
    s.mode_incremental = true;
    s.seconds_total = run_->clock.seconds();
    // Per-phase times of this update (not of the first solve): no build; linking is the
    // link update; the rest is re-solving.
    s.seconds_build = 0;
    s.seconds_link = s.seconds_adjust;
    s.seconds_solve = s.seconds_total - s.seconds_adjust;
    set_progress(1.0);
    solved_ = true;
}

}  // namespace radiosity
