// The solver's side of the direct light (DirectLight, direct_light.h): a light set anew, the
// steps of a solve and an update that split, light and coarsen elements through it (the
// hierarchy and the element count stay the solver's), the judgements made on the lamps'
// first bounce, and the irradiance the lighting-only output reads.
#include <algorithm>
#include <array>
#include <functional>

#include "radiosity/corner_values.h"
#include "radiosity/solver.h"

namespace radiosity {

void Solver::set_light(int index, const LightDesc& l) {
    settle_preview();
    if (index < 0 || index >= int(scene_.lights().size()))
        throw InputError("set_light: unknown light " + std::to_string(index));
    l.validate();
    LightDesc d = l;
    d.direction = normalize(d.direction);
    scene_.lights_mut()[index] = d;
    direct_light_.relight();
    edits_.record_materials();  // the update path re-derives the reference radiance and re-solves
}

void Solver::light_initial() {
    // The initial linking judges links by their senders' radiance: without this, surfaces lit
    // only by lamps would look dark to it (their light arrives only with the first sweep) and
    // the first links would be too coarse, leaving the refinement rounds to catch up.
    if (scene_.lights().empty()) return;
    collect_receivers(nullptr);
    light_refine(nullptr);
    collect_receivers(nullptr);
    gathering_.sweep(gather_context());
}

void Solver::light_update(const UpdateRun& u) {
    // An update's first step for the lights (adjust.cpp): lights or placements changed, so
    // the splits the new direct light does not need go before the remaining leaves are lit
    // again (the old leaves there would cost rays for nothing), and the new light splits
    // where it needs, as light_initial does before a full solve's first linking: the oracle
    // then judges links by the radiances the new light's elements give. (Split only in the
    // first refinement round, after the first gather, links would be judged on the old,
    // coarser light elements and refined for good.)
    if (scene_.lights().empty()) return;
    direct_light_.invalidate(h_, edits_.poses(), replay_boxes(&u));
    if (!direct_light_.take_recheck()) return;
    light_coarsen(&u);
    collect_receivers(&u);
    if (light_refine(&u)) collect_receivers(&u);
}

bool Solver::light_refine(const UpdateRun* u) {
    if (scene_.lights().empty()) return false;
    if (direct_light_.take_recheck()) light_coarsen(u);
    return direct_light_.refine(h_, light_sight(), tolerances_.threshold, gathering_.leaves(), [this](int id) {
        // A shadow's edge splits below the area floor too (may_split_below_floor): a floor
        // leaf across it sends its half-lit average under the object that casts it.
        const Oracle o = oracle();  // made here: the element count grows with each split
        if (!(o.can_split(id) || o.may_split_below_floor(id))) return false;
        h_.subdivide(id);
        stats_.element_nodes += 4;
        return true;
    });
}

bool Solver::light_coarsen(const UpdateRun* u) {
    // After a light moved or changed (or objects moved), elements split only for the old
    // direct light merge back where the new light does not need them, so an incremental
    // update ends with the elements a full solve would make (3.4's un-refinement, for
    // lights).
    std::vector<char> referenced(h_.nodes.size(), 0);
    for (const Link& l : links_)
        if (!l.dead) referenced[l.src] = referenced[l.rcv] = 1;
    const std::vector<int> drop = direct_light_.coarsen(h_, light_sight(), tolerances_.threshold, referenced);
    for (int id : drop) stats_.element_nodes -= h_.retire_below(id);
    if (!drop.empty()) collect_receivers(u);
    return !drop.empty();
}

void Solver::at_first_bounce(const std::function<void()>& judge_links, const std::vector<char>* only) {
    // A full solve of a lit scene makes its first linking on the radiance light_initial's
    // sweep leaves (emission + rho x lamp light, no interreflection yet), and most of its
    // oracle decisions then stand: a settlement (3.5) is never judged again. An update's
    // first judgement of links whose senders' light changed is made on that same radiance,
    // swapped in for it and back; judged on converged radiance instead, links beside a box's
    // foot that a full solve settles would be split, and the update would differ from it.
    // `only`: the leaves to swap (per node); the others keep their radiance, and their element
    // ancestors and clusters are averaged again over both.
    const size_t nn = h_.nodes.size();
    // The solved radiance comes back however judge_links ends (a cancel throws).
    struct Saved {
        Hierarchy& h;
        size_t nn;
        std::vector<Rgb> L, lo, hi;
        std::vector<std::array<Rgb, kBins>> S;
        ~Saved() {
            for (size_t i = 0; i < nn; ++i) {
                Node& n = h.nodes[i];
                n.L = L[i], n.Lmin = lo[i], n.Lmax = hi[i], n.S = S[i];
            }
            // Elements split meanwhile inherit their parent's radiance, as subdivide does.
            for (size_t i = nn; i < h.nodes.size(); ++i) {
                Node& n = h.nodes[i];
                if (n.is_cluster() || n.parent < 0) continue;
                n.L = n.Lmin = n.Lmax = h.nodes[n.parent].L;
            }
        }
    } saved{h_, nn, std::vector<Rgb>(nn), std::vector<Rgb>(nn), std::vector<Rgb>(nn),
            std::vector<std::array<Rgb, kBins>>(nn)};
    for (size_t i = 0; i < nn; ++i) {
        const Node& n = h_.nodes[i];
        saved.L[i] = n.L, saved.lo[i] = n.Lmin, saved.hi[i] = n.Lmax, saved.S[i] = n.S;
    }
    for (size_t i = nn; i-- > 0;) {  // children (larger ids) before their parents
        Node& n = h_.nodes[i];
        if (n.dead || n.is_cluster()) continue;
        if (n.children.empty()) {
            if (!only || (i < only->size() && (*only)[i])) n.L = n.Lmin = n.Lmax = n.emission + n.rho * direct_light_.direct(int(i));
            continue;
        }
        Rgb sum, mn = Rgb::all(1e300), mx = Rgb::all(-1e300);
        double area = 0;
        for (int c : n.children) {
            const Node& k = h_.nodes[c];
            sum += k.L * k.area;
            area += k.area;
            mn = cmin(mn, k.Lmin);
            mx = cmax(mx, k.Lmax);
        }
        n.L = area > 0 ? sum / area : n.emission;
        n.Lmin = mn;
        n.Lmax = mx;
    }
    Gathering::pull_up_clusters(h_);
    judge_links();
}

Rgb Solver::leaf_irradiance(int id) const {
    settle_preview();
    // What push_pull gathers for this leaf (gather_plan.cpp), without the reflectance: light
    // arriving through element links on the leaf and its ancestors, and through cluster links
    // above its surface times its own cosine; closure-corrected; plus the direct term.
    const Node& n = h_.nodes[id];
    Rgb acc;
    for (int a = id; a >= 0 && !h_.nodes[a].is_cluster(); a = h_.nodes[a].parent)
        if (!h_.nodes[a].in_links.empty()) acc += h_.nodes[a].G;
    for (int a : h_.ancestors_of_surface(n.surface))
        for (int li : h_.nodes[a].in_links) {
            const Link& l = links_[li];
            double c = -dot(n.normal, l.dir);
            if (c > 0 && h_.holds_pocket(l.src, n.pocket)) acc += l.value * c;  // gather_plan.cpp's rule
        }
    const Rgb own = n.in_links.empty() ? Rgb{} : n.G;
    const ClosureFactors& k = gathering_.enclosure().factors(id);
    return closure_gathered(own, acc, k.c_own, k.c_inherited, k.fill, n.L) + direct_light_.direct(id);
}

std::vector<float> Solver::corner_irradiance(int object) const {
    settle_preview();
    if (object < 0 || object >= int(scene_.objects().size()))
        throw std::out_of_range("unknown object " + std::to_string(object));
    // (output.cpp: the final gather's points, or the leaves)
    return gathered_or_leaves({h_, scene_, direct_light_, settings_.crease_angle_deg}, object, settings_.gather_rays > 0 ? output_.corner_irradiance(h_, object) : std::vector<float>{},
                              [this](int id) { return leaf_irradiance(id); });
}

}  // namespace radiosity
