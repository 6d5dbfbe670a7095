// The gather plan (gather_plan.h): building it from the hierarchy and links, one Jacobi sweep
// over it (gathering, push-pull), and copying the radiances back.
#include "radiosity/gather_plan.h"
#include "radiosity/held_bytes.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>

#include "radiosity/enclosure.h"
#include "radiosity/parallel.h"

namespace radiosity {

namespace {
// How many items ahead the flat build passes fetch the Link or Node they will read: far
// enough to hide a memory access behind the work on the items in between.
constexpr size_t kAhead = 16;
// Starting a thread costs tens of microseconds (more on a busy machine): a plan with less
// work than this (links + elements) is built and swept on the calling thread.
constexpr size_t kParallelFrom = 65536;

// Irradiance / pi (all colours alike) that the links into a node bring from unit senders.
Rgb unit_gather(const Hierarchy& h, const Node& n, const LinkStore& links) {
    Rgb g;
    for (int li : n.in_links)
        if (h.closes(links[size_t(li)].src)) g += Rgb::all(1.0) * links[size_t(li)].K;
    return g;
}

void unit_push_down(const Hierarchy& h, const LinkStore& links, int id, Rgb acc, CouplingSums& sums) {
    const Node& n = h.nodes[size_t(id)];
    const Rgb own = n.in_links.empty() ? Rgb{} : unit_gather(h, n, links);
    acc += own;
    if (n.children.empty()) {
        sums.total[size_t(id)] = acc.mean();
        sums.own[size_t(id)] = own.mean();
        return;
    }
    for (int c : n.children) unit_push_down(h, links, c, acc, sums);
}

}  // namespace

void coupling_sums(const Hierarchy& h, const LinkStore& links, CouplingSums& sums, int threads) {
    // The links into clusters that can bring light (their senders close the view), per
    // cluster in in_links order, copied once: a cluster high up is above thousands of
    // surfaces, and its links read from the store would each be a miss.
    struct Term {
        Vec3 dir;
        double K;
        int src;
        bool closes;  // Hierarchy::closes(src)
    };
    std::vector<int64_t> begin(h.nodes.size() + 1, 0);
    for (size_t id = 0; id < h.nodes.size(); ++id) {
        const Node& n = h.nodes[id];
        begin[id + 1] = begin[id] + (n.is_cluster() ? int64_t(n.in_links.size()) : 0);
    }
    std::vector<Term> terms(size_t(begin.back()));
    parallel_for(h.nodes.size(), threads, [&](size_t id) {
        const Node& n = h.nodes[id];
        if (!n.is_cluster()) return;
        for (size_t k = 0; k < n.in_links.size(); ++k) {
            const Link& l = links[size_t(n.in_links[k])];
            terms[size_t(begin[id]) + k] = {l.dir, l.K, l.src, h.closes(l.src)};
        }
    }, 256);
    parallel_for(h.surfaces.size(), threads, [&](size_t s) {
        const Node& root = h.nodes[size_t(h.surfaces[s].root)];
        const Vec3 nrm = root.normal;
        Rgb acc;  // through the cluster links above the surface, times its cosine toward each
        for (int a : h.ancestors_of_surface(int(s)))
            for (int64_t t = begin[size_t(a)]; t < begin[size_t(a) + 1]; ++t) {
                const Term& l = terms[size_t(t)];
                const double c = -dot(nrm, l.dir);
                if (c > 0 && h.holds_pocket(l.src, root.pocket) && l.closes) acc += (Rgb::all(1.0) * l.K) * c;
            }
        unit_push_down(h, links, h.surfaces[s].root, acc, sums);
    }, 64);
}

int GatherPlan::workers(int threads) const {
    return plink_id_.size() + size_t(n_elem_) < kParallelFrom ? 1 : threads;
}

int32_t GatherPlan::slot_of(int node) {
    if (slot_[size_t(node)] < 0) {
        // A node outside the element trees and clusters that a link still names (not expected
        // from the solver's bookkeeping): its radiance stays what it is, as in a sweep over
        // the nodes.
        slot_[size_t(node)] = int32_t(slot_node_.size());
        slot_node_.push_back(node);
    }
    return slot_[size_t(node)];
}

void GatherPlan::build(const Hierarchy& h, const LinkStore& links, int threads) {
    valid_ = radiometry_ = dirty_ = false;  // until the build completes (it may throw bad_alloc)
    built_links_ = links.size();
    built_nodes_ = h.nodes.size();
    slot_.assign(h.nodes.size(), -1);
    slot_node_.clear();
    build_elements(h);
    const std::vector<int32_t> c_value_begin = build_clusters(h);
    ClusterLinkEnds ends;
    build_links(h, links, threads, ends);
    build_flux_groups(h, c_value_begin, ends, threads);
    valid_ = true;
}

// Element entries: each surface's quadtree breadth first. Element receivers and their
// in_links (the order a gather sums them in) are taken on the way. A node is fetched when
// it joins the queue, well before it is read.
void GatherPlan::build_elements(const Hierarchy& h) {
    auto fetch = [&](int id) {
        __builtin_prefetch(&h.nodes[size_t(id)].children);
        __builtin_prefetch(&h.nodes[size_t(id)].in_links);
    };
    const size_t ns = h.surfaces.size();
    s_begin_.assign(ns + 1, 0);
    e_child_.clear();
    e_nchild_.clear();
    e_rcv_.clear();
    r_entry_.clear();
    r_begin_.clear();
    plink_id_.clear();
    for (size_t s = 0; s < ns; ++s) {
        if (s + 4 < ns) fetch(h.surfaces[s + 4].root);
        s_begin_[s] = int32_t(slot_node_.size());
        const int root = h.surfaces[s].root;
        slot_[size_t(root)] = int32_t(slot_node_.size());
        slot_node_.push_back(root);
        for (size_t i = size_t(s_begin_[s]); i < slot_node_.size(); ++i) {
            const Node& n = h.nodes[size_t(slot_node_[i])];
            e_child_.push_back(n.children.empty() ? -1 : int32_t(slot_node_.size()));
            e_nchild_.push_back(uint8_t(n.children.size()));
            e_rcv_.push_back(!n.in_links.empty());
            if (!n.in_links.empty()) {
                r_entry_.push_back(int32_t(i));
                r_begin_.push_back(int32_t(plink_id_.size()));
                plink_id_.insert(plink_id_.end(), n.in_links.begin(), n.in_links.end());
            }
            for (int c : n.children) {
                fetch(c);
                slot_[size_t(c)] = int32_t(slot_node_.size());
                slot_node_.push_back(c);
            }
        }
    }
    s_begin_[ns] = int32_t(slot_node_.size());
    n_elem_ = int32_t(slot_node_.size());
    const size_t ne = size_t(n_elem_);
    r_begin_.push_back(int32_t(plink_id_.size()));
    G_.assign(ne, Rgb{});
    acc_.assign(ne, Rgb{});
}

// Clusters by decreasing node id: a cluster's child clusters have larger ids, so one forward
// pass over them pulls up bottom-up. Then the links into clusters, after the element
// receivers' links, each with its own value. Returns per cluster the index in cvalue_ of its
// first link's value (-1: no links into it).
std::vector<int32_t> GatherPlan::build_clusters(const Hierarchy& h) {
    cluster_links_from_ = int32_t(plink_id_.size());
    n_clusters_ = 0;
    for (size_t id = h.nodes.size(); id-- > 0;)
        if (h.nodes[id].is_cluster()) {
            slot_[id] = int32_t(slot_node_.size());
            slot_node_.push_back(int32_t(id));
            ++n_clusters_;
        }
    cr_node_.clear();
    std::vector<int32_t> c_value_begin(size_t(n_clusters_), -1);
    for (int32_t ci = 0; ci < n_clusters_; ++ci) {
        const int id = slot_node_[size_t(n_elem_ + ci)];
        const Node& c = h.nodes[size_t(id)];
        if (c.dead || c.in_links.empty()) continue;
        cr_node_.push_back(id);
        c_value_begin[size_t(ci)] = int32_t(plink_id_.size()) - cluster_links_from_;
        plink_id_.insert(plink_id_.end(), c.in_links.begin(), c.in_links.end());
    }
    return c_value_begin;
}

// Sender slot and K of every link, in one flat pass that fetches links ahead (a link read is a
// cache miss; this way the misses overlap), and the links into clusters' directions and
// senders for the flux groups (`ends`). Cluster senders and element senders with samples
// are marked -2 and senders outside the plan -3 for the serial pass after, which gives the
// former their sender records and the latter their slots.
void GatherPlan::build_links(const Hierarchy& h, const LinkStore& links, int threads, ClusterLinkEnds& ends) {
    const int32_t cl_lo = n_elem_, cl_hi = n_elem_ + n_clusters_;
    plinks_.resize(plink_id_.size());
    const size_t from = size_t(cluster_links_from_);
    ends.dir.resize(plinks_.size() - from);
    ends.src.resize(plinks_.size() - from);
    parallel_for(plinks_.size(), workers(threads), [&](size_t k) {
        if (k + kAhead < plink_id_.size()) __builtin_prefetch(&links[size_t(plink_id_[k + kAhead])]);
        const Link& l = links[size_t(plink_id_[k])];
        if (k >= from) {
            ends.dir[k - from] = l.dir;
            ends.src[k - from] = l.src;
        }
        const int32_t src = slot_[size_t(l.src)];
        const int32_t send = src < 0 ? -3 : ((src >= cl_lo && src < cl_hi) || !l.samples.empty() ? -2 : -1);
        plinks_[k] = PlanLink{src, send, l.K, h.closes(l.src) ? l.K : 0.0};
    }, 4096);
    send_at_.clear();
    for (size_t k = 0; k < plinks_.size(); ++k) {
        PlanLink& p = plinks_[k];
        if (p.send == -3) {
            p.src = slot_of(links[size_t(plink_id_[k])].src);
            p.send = -1;
        } else if (p.send == -2) {
            p.send = int32_t(send_at_.size());
            send_at_.push_back(int32_t(k));
        }
    }
    cvalue_.assign(plinks_.size() - size_t(cluster_links_from_), Rgb{});
}

namespace {
// A double's bits, as a map key: exact equality, and a NaN (never expected) cannot upset the
// map's ordering.
uint64_t bits_of(double x) {
    uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
}
}  // namespace

// Flux through cluster links, per group of surfaces that receive the same: the same ancestor
// chain (the same deepest ancestor), the same normal (keyed by its bits) and the same pocket
// (a link brings nothing to surfaces in pockets its sender has none in). Terms in the order
// the ancestors (root first) and their in_links come, as a per-surface walk would add them.
void GatherPlan::build_flux_groups(const Hierarchy& h, const std::vector<int32_t>& c_value_begin,
                                   const ClusterLinkEnds& ends, int threads) {
    const int32_t cl_lo = n_elem_, cl_hi = n_elem_ + n_clusters_;
    const size_t ns = h.surfaces.size();
    // The groups, in order of their first surface (which stands for the group's terms).
    std::map<std::tuple<int, uint64_t, uint64_t, uint64_t, int>, int32_t> groups;
    std::vector<int32_t> first;
    s_group_.assign(ns, 0);
    for (size_t s = 0; s < ns; ++s) {
        const Vec3 nrm = h.nodes[size_t(h.surfaces[s].root)].normal;
        const std::vector<int>& anc = h.ancestors_of_surface(int(s));
        const auto key = std::make_tuple(anc.empty() ? -1 : anc.back(), bits_of(nrm.x), bits_of(nrm.y), bits_of(nrm.z),
                                         h.nodes[size_t(h.surfaces[s].root)].pocket);
        const auto [it, made] = groups.emplace(key, int32_t(first.size()));
        if (made) first.push_back(int32_t(s));
        s_group_[s] = it->second;
    }
    // Their terms, a run of groups a chunk: filled in parallel, each group's in the order a
    // per-surface walk adds them.
    const size_t ng = first.size();
    const size_t per = std::max<size_t>(64, (ng + kFluxChunks - 1) / kFluxChunks);
    const size_t nc = (ng + per - 1) / per;
    flux_.resize(nc);
    g_chunk_.resize(ng);
    g_begin_.resize(ng);
    g_end_.resize(ng);
    parallel_for(nc, ng < 4096 ? 1 : threads, [&](size_t c) {
        std::vector<FluxTerm>& out = flux_[c];
        out.clear();
        for (size_t g = c * per; g < std::min(ng, (c + 1) * per); ++g) {
            const int s = first[g];
            const Node& root = h.nodes[size_t(h.surfaces[size_t(s)].root)];
            g_chunk_[g] = int32_t(c);
            g_begin_[g] = int32_t(out.size());
            for (int a : h.ancestors_of_surface(s)) {
                const int32_t sa = slot_[size_t(a)];
                const int32_t from = sa >= cl_lo && sa < cl_hi ? c_value_begin[size_t(sa - cl_lo)] : -1;
                if (from < 0) continue;  // no links into it
                // (The links' ends as build_links copied them: one ancestor high up serves
                // thousands of groups, and its links read from the store would each be a miss.)
                const int32_t count = int32_t(h.nodes[size_t(a)].in_links.size());
                for (int32_t k = from; k < from + count; ++k) {
                    const double cs = -dot(root.normal, ends.dir[size_t(k)]);
                    if (cs > 0 && h.holds_pocket(ends.src[size_t(k)], root.pocket)) out.push_back({k, cs});
                }
            }
            g_end_[g] = int32_t(out.size());
        }
    }, 1);
    g_flux_.assign(ng, Rgb{});
}

void GatherPlan::prepare_radiometry(const Hierarchy& h, const LinkStore& links, const Enclosure& enclosure,
                                    const std::function<Rgb(int)>& direct, int threads) {
    if (radiometry_) return;
    prepare_elements(h, enclosure, direct, threads);
    prepare_clusters(h);
    prepare_sends(h, links, threads);
    for (size_t k = 0; k < cvalue_.size(); ++k) cvalue_[k] = links[size_t(plink_id_[size_t(cluster_links_from_) + k])].value;
    // Radiances of clusters and of the nodes outside the trees.
    L_.resize(slot_node_.size());
    for (size_t i = size_t(n_elem_); i < slot_node_.size(); ++i) L_[i] = h.nodes[size_t(slot_node_[i])].L;
    radiometry_ = true;
}

// Elements: areas and radiances, and at the leaves the materials, closure factors and direct
// light; then each inner element's children's area, as the pull-up divides by it.
void GatherPlan::prepare_elements(const Hierarchy& h, const Enclosure& enclosure, const std::function<Rgb(int)>& direct,
                                  int threads) {
    const size_t ne = size_t(n_elem_);
    e_area_.assign(ne, 0.0);
    e_child_area_.assign(ne, 0.0);
    e_closure_.assign(ne, 1.0);
    e_closure_own_.assign(ne, 1.0);
    e_fill_.assign(ne, 0.0);
    e_emission_.assign(ne, Rgb{});
    e_rho_.assign(ne, Rgb{});
    e_direct_.assign(ne, Rgb{});
    L_.assign(ne, Rgb{});
    // In node order: the nodes are read front to back, which the hardware prefetches.
    parallel_for(h.nodes.size(), workers(threads), [&](size_t id) {
        const int32_t sl = slot_[id];
        if (sl < 0 || sl >= n_elem_) return;
        const size_t i = size_t(sl);
        const Node& n = h.nodes[id];
        e_area_[i] = n.area;
        e_emission_[i] = n.emission;
        L_[i] = n.L;
        if (e_child_[i] < 0) {
            e_rho_[i] = n.rho;
            const ClosureFactors& k = enclosure.factors(int(id));
            e_closure_[i] = k.c_inherited;
            e_closure_own_[i] = k.c_own;
            e_fill_[i] = k.fill;
            e_direct_[i] = direct(int(id));
        }
    }, 2048);
    for (size_t i = 0; i < ne; ++i) {  // cheap (the plan's own arrays): no thread worth starting
        double area = 0;  // summed in children order, as the pull-up sums it
        for (int32_t c = e_child_[i]; c >= 0 && c < e_child_[i] + e_nchild_[i]; ++c) area += e_area_[size_t(c)];
        e_child_area_[i] = area;
    }
}

// Clusters: bins and children for the pull-up.
void GatherPlan::prepare_clusters(const Hierarchy& h) {
    S_.assign(size_t(n_clusters_) * kBins, Rgb{});
    c_begin_.assign(size_t(n_clusters_) + 1, 0);
    c_children_.clear();
    for (int32_t ci = 0; ci < n_clusters_; ++ci) {
        const Node& c = h.nodes[size_t(slot_node_[size_t(n_elem_ + ci)])];
        for (int b = 0; b < kBins; ++b) S_[size_t(ci) * kBins + size_t(b)] = c.S[size_t(b)];
        c_begin_[size_t(ci)] = int32_t(c_children_.size());
        for (int k : c.children) {
            const Node& n = h.nodes[size_t(k)];
            ClusterChild cc{};
            cc.slot = slot_of(k);
            cc.area = n.area;
            cc.cluster = n.is_cluster() ? cc.slot - n_elem_ : -1;
            for (int a = 0; a < 3; ++a) {
                const double v = n.normal[a] * n.area;
                cc.bin[a] = bin_of(a, v);
                cc.proj[a] = std::fabs(v);
            }
            c_children_.push_back(cc);
        }
    }
    c_begin_[size_t(n_clusters_)] = int32_t(c_children_.size());
}

// Cluster senders: records and their samples, flattened. First the ranges (a link's sample
// count, and where its list is, for fetching it ahead), then the copies (in parallel); a
// sample node outside the plan (not expected: samples are surface roots) gets its slot in a
// serial pass after.
void GatherPlan::prepare_sends(const Hierarchy& h, const LinkStore& links, int threads) {
    sends_.assign(send_at_.size(), ClusterSend{});
    auto link_of = [&](size_t k) -> const Link& { return links[size_t(plink_id_[size_t(send_at_[k])])]; };
    std::vector<const std::pair<int, float>*> lists(send_at_.size());
    int32_t nsamples = 0;
    for (size_t k = 0; k < sends_.size(); ++k) {
        if (k + kAhead < send_at_.size()) __builtin_prefetch(&link_of(k + kAhead).samples);
        const Link& l = link_of(k);
        lists[k] = l.samples.data();
        sends_[k].sample_begin = nsamples;
        nsamples += int32_t(l.samples.size());
        sends_[k].sample_end = nsamples;
    }
    samples_.resize(size_t(nsamples));
    // Each node's live element's slot, in one pass over the nodes: resolving each sample
    // through its node (dead? parent?) would be a cache miss per sample.
    std::vector<int32_t> live_slot(h.nodes.size());
    parallel_for(h.nodes.size(), workers(threads), [&](size_t id) { live_slot[id] = slot_[size_t(h.live_element(int(id)))]; }, 4096);
    std::atomic<bool> outside{false};
    parallel_for(send_at_.size(), workers(threads), [&](size_t k) {
        if (k + kAhead < lists.size() && lists[k + kAhead]) __builtin_prefetch(lists[k + kAhead]);
        const PlanLink& p = plinks_[size_t(send_at_[k])];
        ClusterSend& cs = sends_[k];
        cs.src = p.src;
        const int32_t n = cs.sample_end - cs.sample_begin;
        double w = 0;  // in samples order, as sender_radiance sums it
        for (int32_t j = 0; j < n; ++j) {
            const int32_t sl = live_slot[size_t(lists[k][j].first)];
            if (sl < 0) outside = true;
            samples_[size_t(cs.sample_begin + j)] = {sl, lists[k][j].second};
            w += lists[k][j].second;
        }
        cs.wsum = w;
        if (n == 0) {
            const Link& l = link_of(k);
            const Node& src = h.nodes[size_t(l.src)];
            const int32_t ci = p.src - n_elem_;
            for (int a = 0; a < 3; ++a) {
                const double wa = l.dir[a] * l.dir[a];
                if (wa <= 0) continue;
                const int b = bin_of(a, l.dir[a]);
                cs.bin[cs.nbins] = ci * kBins + b;
                cs.w[cs.nbins] = wa;
                cs.den += src.W[size_t(b)] * wa;
                ++cs.nbins;
            }
        }
    }, 256);
    if (outside)
        for (size_t k = 0; k < sends_.size(); ++k)
            for (int32_t j = sends_[k].sample_begin; j < sends_[k].sample_end; ++j)
                if (samples_[size_t(j)].slot < 0)
                    samples_[size_t(j)].slot = slot_of(h.live_element(link_of(k).samples[size_t(j - sends_[k].sample_begin)].first));
}

// Sender radiance as transfer.cpp's sender_radiance computes it, from the plan's arrays.
Rgb GatherPlan::sender_radiance(const PlanLink& p) const {
    if (p.send < 0) return L_[size_t(p.src)];
    const ClusterSend& c = sends_[size_t(p.send)];
    if (c.sample_begin < c.sample_end) {
        Rgb acc;
        for (int32_t k = c.sample_begin; k < c.sample_end; ++k)
            acc += L_[size_t(samples_[size_t(k)].slot)] * double(samples_[size_t(k)].weight);
        return acc / c.wsum;
    }
    Rgb num;
    for (int32_t b = 0; b < c.nbins; ++b) num += S_[size_t(c.bin[b])] * c.w[b];
    return c.den > 0 ? num / c.den : L_[size_t(c.src)];
}

void GatherPlan::push_pull(size_t s, bool unit, CouplingSums* sums, double& delta) {
    const int32_t b = s_begin_[s], e = s_begin_[s + 1];
    acc_[size_t(b)] = g_flux_[size_t(s_group_[s])];
    if (e_rcv_[size_t(b)]) acc_[size_t(b)] += G_[size_t(b)];
    // Push irradiance down (parents come before children) and reflect it at the leaves.
    for (int32_t i = b; i < e; ++i) {
        const int32_t c0 = e_child_[size_t(i)];
        if (c0 >= 0) {
            for (int32_t c = c0; c < c0 + e_nchild_[size_t(i)]; ++c) {
                acc_[size_t(c)] = acc_[size_t(i)];
                if (e_rcv_[size_t(c)]) acc_[size_t(c)] += G_[size_t(c)];
            }
            continue;
        }
        const Rgb own = e_rcv_[size_t(i)] ? G_[size_t(i)] : Rgb{};  // through the leaf's own links
        if (unit) {
            const size_t node = size_t(slot_node_[size_t(i)]);
            sums->total[node] = acc_[size_t(i)].mean();
            sums->own[node] = own.mean();
            continue;
        }
        const Rgb gathered = closure_gathered(own, acc_[size_t(i)], e_closure_own_[size_t(i)], e_closure_[size_t(i)],
                                              e_fill_[size_t(i)], L_[size_t(i)]);
        const Rgb Lnew = e_emission_[size_t(i)] + e_rho_[size_t(i)] * (gathered + e_direct_[size_t(i)]);
        const Rgb Lold = L_[size_t(i)];
        delta = std::max(delta, std::fabs((Lnew - Lold).max()));
        delta = std::max(delta, std::fabs((Lold - Lnew).max()));
        L_[size_t(i)] = Lnew;
    }
    if (unit) return;
    // Pull radiance up, area-weighted (a reverse pass: children before their parent).
    for (int32_t i = e - 1; i >= b; --i) {
        const int32_t c0 = e_child_[size_t(i)];
        if (c0 < 0) continue;
        Rgb sum;
        for (int32_t c = c0; c < c0 + e_nchild_[size_t(i)]; ++c) sum += L_[size_t(c)] * e_area_[size_t(c)];
        const double area = e_child_area_[size_t(i)];
        L_[size_t(i)] = area > 0 ? sum / area : e_emission_[size_t(i)];
    }
}

void GatherPlan::pull_up_clusters() {
    for (int32_t ci = 0; ci < n_clusters_; ++ci) {
        Rgb* S = &S_[size_t(ci) * kBins];
        std::fill(S, S + kBins, Rgb{});
        Rgb sum;
        double area = 0;
        for (int32_t k = c_begin_[size_t(ci)]; k < c_begin_[size_t(ci) + 1]; ++k) {
            const ClusterChild& cc = c_children_[size_t(k)];
            const Rgb L = L_[size_t(cc.slot)];
            if (cc.cluster >= 0) {
                const Rgb* Sc = &S_[size_t(cc.cluster) * kBins];
                for (int b = 0; b < kBins; ++b) S[b] += Sc[b];
            } else {
                for (int a = 0; a < 3; ++a) S[cc.bin[a]] += L * cc.proj[a];
            }
            sum += L * cc.area;
            area += cc.area;
        }
        L_[size_t(n_elem_ + ci)] = area > 0 ? sum / area : Rgb{};
    }
}

double GatherPlan::sweep(bool unit, CouplingSums* sums, int threads) {
    // 1. Gather through the links (Jacobi: from the previous sweep's radiances): element
    //    receivers sum theirs, each link into a cluster keeps its own value.
    const size_t ner = r_entry_.size();
    parallel_for(ner + cvalue_.size(), workers(threads), [&](size_t i) {
        if (i >= ner) {
            const PlanLink& p = plinks_[size_t(cluster_links_from_) + (i - ner)];
            cvalue_[i - ner] = unit ? Rgb::all(p.unit_K) : sender_radiance(p) * p.K;
            return;
        }
        Rgb g;
        for (int32_t k = r_begin_[i]; k < r_begin_[i + 1]; ++k) {
            const PlanLink& p = plinks_[size_t(k)];
            g += unit ? Rgb::all(p.unit_K) : sender_radiance(p) * p.K;
        }
        G_[size_t(r_entry_[i])] = g;
    }, 64);
    // 2. Flux arriving through cluster links, per surface group, times its cosine (oriented
    //    clusters); then push-pull down and up each surface's quadtree.
    parallel_for(g_flux_.size(), workers(threads), [&](size_t g) {
        Rgb acc;
        const FluxTerm* f = flux_[size_t(g_chunk_[g])].data();
        for (int32_t k = g_begin_[g]; k < g_end_[g]; ++k) acc += cvalue_[size_t(f[k].value)] * f[k].cos;
        g_flux_[g] = acc;
    }, 256);
    std::vector<double> deltas(s_group_.size(), 0.0);
    parallel_for(s_group_.size(), workers(threads), [&](size_t s) { push_pull(s, unit, sums, deltas[s]); }, 64);
    if (unit) return 0.0;
    // 3. Clusters: radiance and axis bins from their children.
    pull_up_clusters();
    dirty_ = true;
    double d = 0;
    for (double x : deltas) d = std::max(d, x);
    return d;
}

void GatherPlan::write_back(Hierarchy& h, LinkStore& links, int threads) {
    if (!dirty_) return;
    dirty_ = false;
    // Range of leaf radiance below every node, in the plan's arrays: bottom-up per surface
    // (an inner node's range from its children's), then clusters (children first).
    const size_t nslots = slot_node_.size();
    lo_.resize(nslots);
    hi_.resize(nslots);
    parallel_for(s_group_.size(), workers(threads), [&](size_t s) {
        for (int32_t i = s_begin_[s + 1] - 1; i >= s_begin_[s]; --i) {
            const int32_t c0 = e_child_[size_t(i)];
            if (c0 < 0) {
                lo_[size_t(i)] = hi_[size_t(i)] = L_[size_t(i)];
                continue;
            }
            Rgb lo = Rgb::all(1e300), hi = Rgb::all(-1e300);
            for (int32_t c = c0; c < c0 + e_nchild_[size_t(i)]; ++c) {
                lo = cmin(lo, lo_[size_t(c)]);
                hi = cmax(hi, hi_[size_t(c)]);
            }
            lo_[size_t(i)] = lo;
            hi_[size_t(i)] = hi;
        }
    }, 64);
    const size_t first_extra = size_t(n_elem_ + n_clusters_);
    for (size_t i = first_extra; i < nslots; ++i) {  // nodes outside the plan keep theirs
        lo_[i] = h.nodes[size_t(slot_node_[i])].Lmin;
        hi_[i] = h.nodes[size_t(slot_node_[i])].Lmax;
    }
    for (int32_t ci = 0; ci < n_clusters_; ++ci) {
        Rgb lo = Rgb::all(1e300), hi = Rgb::all(-1e300);
        for (int32_t k = c_begin_[size_t(ci)]; k < c_begin_[size_t(ci) + 1]; ++k) {
            lo = cmin(lo, lo_[size_t(c_children_[size_t(k)].slot)]);
            hi = cmax(hi, hi_[size_t(c_children_[size_t(k)].slot)]);
        }
        const bool empty = c_begin_[size_t(ci)] == c_begin_[size_t(ci) + 1];
        lo_[size_t(n_elem_ + ci)] = empty ? Rgb{} : lo;
        hi_[size_t(n_elem_ + ci)] = empty ? Rgb{} : hi;
    }
    // Into the nodes in node order (front to back through memory, which the hardware
    // prefetches, rather than tree by tree).
    parallel_for(h.nodes.size(), workers(threads), [&](size_t id) {
        const int32_t sl = slot_[id];
        if (sl < 0 || size_t(sl) >= first_extra) return;
        Node& n = h.nodes[id];
        n.L = L_[size_t(sl)];
        n.Lmin = lo_[size_t(sl)];
        n.Lmax = hi_[size_t(sl)];
        if (sl < n_elem_) {
            if (e_rcv_[size_t(sl)]) n.G = G_[size_t(sl)];
        } else {
            const size_t ci = size_t(sl - n_elem_);
            for (int b = 0; b < kBins; ++b) n.S[size_t(b)] = S_[ci * kBins + size_t(b)];
        }
    }, 2048);
    // Clusters receive through their links' values; their G stays zero.
    for (int id : cr_node_) h.nodes[size_t(id)].G = Rgb{};
    for (size_t k = 0; k < cvalue_.size(); ++k) links[size_t(plink_id_[size_t(cluster_links_from_) + k])].value = cvalue_[k];
}

double GatherPlan::bytes(size_t links, size_t nodes) const {
    double b = held_bytes(slot_) + held_bytes(slot_node_) + held_bytes(L_) + held_bytes(e_child_) +
               held_bytes(e_nchild_) + held_bytes(e_rcv_) + held_bytes(e_area_) + held_bytes(e_child_area_) +
               held_bytes(e_emission_) + held_bytes(e_rho_) + held_bytes(e_direct_) + held_bytes(e_closure_) +
               held_bytes(e_closure_own_) + held_bytes(e_fill_) + held_bytes(G_) + held_bytes(acc_) + held_bytes(lo_) +
               held_bytes(hi_) + held_bytes(s_begin_) + held_bytes(s_group_) + held_bytes(g_chunk_) +
               held_bytes(g_begin_) + held_bytes(g_end_) + held_bytes(flux_) + held_bytes(g_flux_) + held_bytes(c_begin_) + held_bytes(c_children_) + held_bytes(S_) +
               held_bytes(r_entry_) + held_bytes(r_begin_) + held_bytes(cr_node_) + held_bytes(cvalue_) +
               held_bytes(plinks_) + held_bytes(plink_id_) + held_bytes(send_at_) + held_bytes(sends_) +
               held_bytes(samples_);
    // Links and nodes beyond those of the last build (all of them before the first) at what
    // plans hold for each: a node's radiances, materials and tree entry, and a stored link's
    // record with its flux terms (history links included, which the plan leaves out), as
    // furnished rooms' plans measure (docs/decisions.md, "The memory estimate counts the gather
    // plan").
    constexpr double kBytesPerNode = 256.0, kBytesPerLink = 64.0;
    if (links > built_links_) b += kBytesPerLink * double(links - built_links_);
    if (nodes > built_nodes_) b += kBytesPerNode * double(nodes - built_nodes_);
    return b;
}

}  // namespace radiosity
