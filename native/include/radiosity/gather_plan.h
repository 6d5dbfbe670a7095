// The gather plan: a compact structure-of-arrays copy of what a Jacobi sweep (paper 2:
// gathering through the links, then push-pull over the hierarchy) reads, built from the
// hierarchy and links and rebuilt whenever they change.
//
// Why: a sweep over the hierarchy itself walks each receiver's in_links into the Link array
// (152 bytes a link) and reads senders from Nodes of several hundred bytes, so it is
// memory-bound. The plan keeps per receiver a contiguous range of 16-byte (sender slot, K)
// records, radiances in one dense array indexed by slot (elements surface by surface, each
// quadtree breadth first, then clusters), and each quadtree as index ranges, so a sweep
// streams through small arrays.
// Surfaces with the same ancestor clusters and the same normal share the flux that cluster
// links bring them (walked once per group instead of once per surface).
//
// Every sum runs over the same terms in the same order as over the hierarchy (in_links order,
// children order, ancestors root first, samples order), so the results are bit-identical.
//
// Built in two steps, both lazily: the structure (trees, links, flux groups) is all a unit
// sweep needs; a radiometric sweep also needs materials, radiances and the cluster senders'
// samples. The plan owns copies of everything it reads (no pointer into links or nodes).
//
// Also here, as the sweeps and the output both use them: CouplingSums (a leaf's couplings
// from unit senders, added up by a unit sweep or by coupling_sums()), ClosureFactors (the
// closure correction those sums give a leaf or an output point, from closure_factors()) and
// closure_gathered(), what a receiver gathers once corrected.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "radiosity/hierarchy.h"
#include "radiosity/link.h"
#include "radiosity/link_store.h"

namespace radiosity {

class Enclosure;  // enclosure.h

// Per node (leaves only filled): the sum of a leaf's couplings from unit senders (mean over
// colours), and the part of it through links at the leaf itself; the rest reaches it through
// links at its ancestors and its clusters. The closure correction weighs them apart.
struct CouplingSums {
    std::vector<double> total, own;
    void reset(size_t nodes) { total.assign(nodes, 0.0), own.assign(nodes, 0.0); }
};

// What a leaf gathers after the closure correction (gathering.cpp set_closure): `own`
// through links at the leaf itself, the rest of `all` through links at its ancestors and
// clusters, each part with its factor, plus the shortfall `fill` taken to see the leaf's own
// radiance L. One formula for the sweeps and for the lighting-only output.
inline Rgb closure_gathered(const Rgb& own, const Rgb& all, double c_own, double c_inherited, double fill, const Rgb& L) {
    return own * c_own + (all - own) * c_inherited + L * fill;
}

// The closure factors of an enclosed receiver (a leaf, or an output point of one) whose
// couplings sum to `own` through its own links and `inherited` through the rest: the reasons
// are at gathering.cpp set_closure. Sums far off 1 (a missing link, not a small error) are
// left alone.
struct ClosureFactors {
    double c_own = 1, c_inherited = 1, fill = 0;
};
inline ClosureFactors closure_factors(double own, double inherited) {
    ClosureFactors c;
    const double f = own + inherited;
    if (!(f > 0.25 && f < 4.0)) return c;
    if (f > 1.0 && own >= 1.0) {
        c.c_own = 1.0 / own;
        c.c_inherited = 0.0;
    } else if (f > 1.0) {
        c.c_inherited = (1.0 - own) / inherited;
    } else {
        c.fill = 1.0 - f;
    }
    return c;
}

// The unit sweep straight from the hierarchy: every sender counts as radiance 1 and each
// leaf's coupling sums go to `sums`, exactly as GatherPlan::sweep(true) computes them. One
// such sweep reads every link once, as building a plan does, so for a single unit sweep (the
// closure correction right after links changed) no plan is built.
void coupling_sums(const Hierarchy& h, const LinkStore& links, CouplingSums& sums, int threads);

class GatherPlan {
public:
    // The structure: element trees, clusters, the active links (every live node's in_links)
    // and the flux groups. Discards the radiometric part.
    void build(const Hierarchy& h, const LinkStore& links, int threads);
    // The radiometric part, once per build: each leaf's emission, reflectance, closure factors
    // (`enclosure`, fitted to the nodes) and direct light (`direct(node)`), radiances as the
    // starting point, cluster senders.
    void prepare_radiometry(const Hierarchy& h, const LinkStore& links, const Enclosure& enclosure,
                            const std::function<Rgb(int)>& direct, int threads);
    // Valid since the last build and not invalidated. `links` and `nodes` are the current
    // sizes: a plan built from fewer is stale even if nobody invalidated it.
    bool valid(size_t links, size_t nodes) const { return valid_ && links == built_links_ && nodes == built_nodes_; }
    bool has_radiometry() const { return radiometry_; }
    void invalidate() { valid_ = radiometry_ = false; }
    int64_t link_count() const { return int64_t(plinks_.size()); }
    // Heap bytes the plan holds (kept while invalid: a rebuild reuses them), and a forecast
    // of what a build from `links` stored links and `nodes` nodes adds to it.
    double bytes(size_t links, size_t nodes) const;

    // One Jacobi sweep on the plan's own radiances. unit: every sender counts as radiance 1 and
    // each leaf's coupling sums go to *sums; returns 0. Otherwise (needs prepare_radiometry)
    // returns the largest change of a leaf radiance.
    double sweep(bool unit, CouplingSums* sums, int threads);

    // Copies the result of the radiometric sweeps since the last build or write-back to the
    // hierarchy and links: L, Lmin, Lmax of elements and clusters, G of receivers, S of
    // clusters, value of links into clusters. A no-op when there was none.
    void write_back(Hierarchy& h, LinkStore& links, int threads);

private:
    // One link as gathered: receiver += K * radiance(sender). send < 0: an element sender,
    // radiance L_[src]; else the cluster sender record sends_[send].
    struct PlanLink {
        int32_t src;
        int32_t send;
        double K;
        double unit_K;  // K in a unit sweep: 0 from a sender that hides nothing (Hierarchy::closes)
    };
    // A cluster sender (or an element sender with samples) as its link sees it (transfer.cpp
    // sender_radiance): the weighted mean of its visible samples, or (none) a projected-area
    // estimate from the axis bins toward the receiver, or the cluster's mean radiance when no
    // bin faces that way.
    struct ClusterSend {
        int32_t sample_begin, sample_end;  // range in samples_
        int32_t src;                       // the cluster's slot (fallback radiance)
        int32_t nbins;                     // bins with a non-zero weight, in axis order
        int32_t bin[3];                    // index into S_
        double w[3];
        double den;                        // sum of W[bin] * w, as sender_radiance sums it
        double wsum;                       // sum of the sample weights, in samples order
    };
    struct Sample {
        int32_t slot;                      // a surface root's slot
        float weight;
    };
    // A child of a cluster in the pull-up: a cluster (its S bins add up) or a surface root
    // (its radiance enters the bins by its projected area along each axis).
    struct ClusterChild {
        int32_t slot;
        int32_t cluster;   // index among clusters, -1 for a surface root
        double area;
        int32_t bin[3];
        double proj[3];    // |normal[axis] * area|
    };
    // A cluster link's flux density times the receiving surfaces' cosine toward it.
    struct FluxTerm {
        int32_t value;     // index in cvalue_
        double cos;
    };

    // The links into clusters, in cvalue_'s order: direction and sender (build()'s scratch).
    struct ClusterLinkEnds {
        std::vector<Vec3> dir;
        std::vector<int> src;
    };

    int32_t slot_of(int node);
    int workers(int threads) const;  // threads, or 1 for a small plan
    // build()'s steps, in order (each described in gather_plan.cpp).
    void build_elements(const Hierarchy& h);
    std::vector<int32_t> build_clusters(const Hierarchy& h);
    void build_links(const Hierarchy& h, const LinkStore& links, int threads, ClusterLinkEnds& ends);
    void build_flux_groups(const Hierarchy& h, const std::vector<int32_t>& c_value_begin, const ClusterLinkEnds& ends,
                           int threads);
    // prepare_radiometry()'s steps, in order.
    void prepare_elements(const Hierarchy& h, const Enclosure& enclosure, const std::function<Rgb(int)>& direct,
                          int threads);
    void prepare_clusters(const Hierarchy& h);
    void prepare_sends(const Hierarchy& h, const LinkStore& links, int threads);
    Rgb sender_radiance(const PlanLink& p) const;
    void push_pull(size_t s, bool unit, CouplingSums* sums, double& delta);
    void pull_up_clusters();

    bool valid_ = false, radiometry_ = false;
    bool dirty_ = false;  // radiometric sweeps ran since the last build or write-back

    // Slots: radiance of every node a sweep reads or writes.
    std::vector<int32_t> slot_;        // per node, -1: not in the plan
    std::vector<int32_t> slot_node_;   // per slot
    std::vector<Rgb> L_;
    // Element entries (slots [0, n_elem_)), surface by surface, each quadtree breadth first so
    // that an inner node's children are a contiguous range after it.
    int32_t n_elem_ = 0;
    std::vector<int32_t> e_child_;     // first child entry, -1 for a leaf
    std::vector<uint8_t> e_nchild_;
    std::vector<uint8_t> e_rcv_;       // has active in-links (its G counts)
    std::vector<double> e_area_, e_child_area_;
    std::vector<Rgb> e_emission_, e_rho_, e_direct_;
    std::vector<double> e_closure_, e_closure_own_, e_fill_;
    std::vector<Rgb> G_, acc_;
    std::vector<Rgb> lo_, hi_;         // per slot, write-back only: range of leaf radiance below
    // Surfaces: entry range and flux group.
    std::vector<int32_t> s_begin_, s_group_;
    // Per group: its terms, g_begin_ to g_end_ in chunk g_chunk_ of flux_ (a run of groups a
    // chunk, so that a build fills them in parallel).
    static constexpr size_t kFluxChunks = 256;
    std::vector<int32_t> g_chunk_, g_begin_, g_end_;
    std::vector<std::vector<FluxTerm>> flux_;
    std::vector<Rgb> g_flux_;
    // Clusters (slots [n_elem_, n_elem_ + n_clusters_)), by decreasing node id so children come
    // before their parents.
    int32_t n_clusters_ = 0;
    std::vector<int32_t> c_begin_;     // range in c_children_
    std::vector<ClusterChild> c_children_;
    std::vector<Rgb> S_;               // kBins per cluster
    // Receivers: element receivers' entries with their link ranges, then the links into
    // clusters, each with its own value (the flux density the surfaces below take).
    std::vector<int32_t> r_entry_, r_begin_;
    int32_t cluster_links_from_ = 0;   // plinks_ index of the first link into a cluster
    std::vector<int32_t> cr_node_;
    std::vector<Rgb> cvalue_;
    std::vector<PlanLink> plinks_;
    std::vector<int32_t> plink_id_;    // per plan link: its id in the solver's links
    std::vector<int32_t> send_at_;     // per cluster sender record: its plan link
    std::vector<ClusterSend> sends_;
    std::vector<Sample> samples_;      // cluster senders' visible samples, flattened
    size_t built_links_ = 0, built_nodes_ = 0;  // sizes of links and nodes the plan was built from
};

}  // namespace radiosity
