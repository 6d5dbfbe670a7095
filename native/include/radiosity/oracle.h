// The oracle: the error-threshold test of a link (Lee & Chuang's refinement oracle, BF-style
// error with a visibility term, and the paper's 3.5 progressive criterion). Given a link, it
// says whether the link transports within the threshold (Keep), which end to split (Src, Rcv),
// or whether the receiver may stay whole with its children's mean coupling (Settle); and which
// elements may split at all. It reads the hierarchy (the nodes' radiance, which the solver sets
// to the radiance it judges on), the settings, the direct light and the threshold state, and
// changes nothing: Refinement (refinement.h) applies its judgements.
#pragma once
#include <cstdint>

#include "radiosity/direct_light.h"
#include "radiosity/hierarchy.h"
#include "radiosity/link.h"
#include "radiosity/settings.h"

namespace radiosity {

class Oracle {
public:
    enum class Side { Keep, Src, Rcv, Settle };
    struct Judgement {
        Side side = Side::Keep;
        double settled_K = 0;  // Settle: the receiver's children's mean coupling
    };
    // The threshold state a solve sets up: the scene-wide threshold (error_threshold x the
    // reference radiance), the reference radiance L_ref, the element area floor, and whether
    // the nodes' radiance estimates the light yet (only then may a link's threshold follow its
    // receiver's light).
    struct Threshold {
        double threshold = 0, reference = 0, min_area = 0;
        bool light_known = false;
    };

    // `elements`: the element nodes made so far (Stats::element_nodes), held against
    // Settings::max_elements. Made for one use and dropped after it, as a DirectLight::Sight
    // is (Solver::oracle): the hierarchy, the settings and the direct light are read through
    // the references at each call, the threshold state and the element count are as given.
    Oracle(const Hierarchy& h, const Settings& settings, const DirectLight& direct_light, const Threshold& threshold,
           int64_t elements)
        : h_(h), settings_(settings), direct_light_(direct_light), t_(threshold), elements_(elements) {}

    // The oracle proper. Errors are in radiance units at the receiver, compared with
    // link_threshold.
    Judgement judge(const Link& l) const;
    // The threshold a link into `receiver` is judged by.
    double link_threshold(const Node& receiver) const;
    // Whether node `id` may split (or has children already): above the area floor, within
    // the element cap.
    bool can_split(int id) const;
    // A leaf element the rules below (and a lamp's shadow edge, DirectLight::refine) may split
    // below the area floor: Settings::below_floor_levels levels under it, within the element cap.
    bool may_split_below_floor(int id) const;

private:
    // judge()'s parts: which end of a link over the threshold to split, and whether a link
    // whose receiver would split may settle instead (3.5).
    static Side split_side(const Link& l, const Node& P, const Node& Q, double err_rcv, double err_src,
                           double threshold, bool ps, bool qs);
    bool settles(const Link& l, const Node& P, const Node& Q, double rho, double Lp, double threshold,
                 double err_src, double& settled_K) const;
    // Whether a link's receiver leaf may split below the area floor because an emitter's
    // outline crosses it.
    bool splits_at_outline(const Link& l, double err_rcv, double threshold) const;
    // Whether node `id`, one end of link l, may split below the area floor because the other
    // end is across a narrow gap from it. `err`: the link's error on id's side.
    bool splits_at_gap(int other, int id, const Link& l, double err, double threshold) const;

    const Hierarchy& h_;
    const Settings& settings_;
    const DirectLight& direct_light_;
    const Threshold t_;
    const int64_t elements_;
};

}  // namespace radiosity
