#include "radiosity/hierarchy.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <string>

#include "radiosity/held_bytes.h"
#include "radiosity/parallel.h"

namespace radiosity {

int Hierarchy::new_node(NodeKind kind, int parent) {
    Node n;
    n.kind = kind;
    n.parent = parent;
    nodes.push_back(std::move(n));
    int id = int(nodes.size()) - 1;
    if (parent >= 0) nodes[parent].children.push_back(id);
    // Clusters are built in the same order for the same scene; elements are keyed by their
    // surface and path so a refinement made in another order gets the same key.
    nodes[id].key = mix(0xC1A5 + uint64_t(kind), uint64_t(id));
    return id;
}

namespace {

// Keys of clusters that are not element quadtrees (see Node::key): from what they stand for,
// never from creation order.
uint64_t name_hash(const std::string& name) {
    uint64_t h = 0xCBF29CE484222325ull;  // FNV-1a
    for (unsigned char c : name) h = (h ^ c) * 0x100000001B3ull;
    return h;
}
// A collection by the names on its path from the root: it keeps its key when collections
// before it in the list come or go.
uint64_t collection_key(const SceneDesc& scene, int c) {
    uint64_t k = 0xC011EC7ull;
    std::vector<int> path;
    for (int a = c; a >= 0; a = scene.clusters()[a].parent) path.push_back(a);
    for (auto it = path.rbegin(); it != path.rend(); ++it) k = Hierarchy::mix(k, name_hash(scene.clusters()[*it].name));
    return k;
}
uint64_t object_tree_key(uint64_t object_key) { return Hierarchy::mix(0x0B1EC7ull, object_key); }

// Newell normal of a polygon of n corners P(0) ... P(n - 1), not normalized (its length is
// twice the area).
template <class Corner>
Vec3 newell_normal(const Corner& P, int n) {
    Vec3 nrm;
    for (int k = 0; k < n; ++k) {
        Vec3 a = P(k), b = P((k + 1) % n);
        nrm.x += (a.y - b.y) * (a.z + b.z);
        nrm.y += (a.z - b.z) * (a.x + b.x);
        nrm.z += (a.x - b.x) * (a.y + b.y);
    }
    return nrm;
}

// Whether a quad is planar and convex about its polygon's normal: only then it stays a quad.
bool planar_convex_quad(const Poly& q, const Vec3& nrm) {
    Vec3 ctr = q.centroid();
    double size = std::sqrt(q.area());
    bool planar = true, convex = true;
    for (int k = 0; k < 4; ++k) {
        if (std::fabs(dot(q.v[k] - ctr, nrm)) > 1e-4 * size) planar = false;
        Vec3 e1 = q.v[(k + 1) % 4] - q.v[k], e2 = q.v[(k + 2) % 4] - q.v[(k + 1) % 4];
        if (dot(cross(e1, e2), nrm) <= 0) convex = false;
    }
    return planar && convex;
}

// The vertex whose fan has only positively oriented triangles, or -1. Testing every vertex is
// O(n^2), too slow for a polygon of 100k corners whose one reflex corner lies near its end, so
// the tests get a budget of O(n). Small polygons are searched in full; when a large one exhausts
// the budget, its reflex corners are tried (a polygon with a single notch fans from the notch).
template <class Corner>
int fan_apex(const Corner& P, int n, const Vec3& nrm) {
    const int64_t budget0 = 32 * int64_t(n) + 1024;
    int64_t budget = budget0;
    auto fans_from = [&](int a) {
        const Vec3 p0 = P(a);
        for (int k = 1; k + 1 < n; ++k) {
            if (--budget < 0) return false;
            Vec3 p1 = P((a + k) % n), p2 = P((a + k + 1) % n);
            if (dot(cross(p1 - p0, p2 - p0), nrm) <= 0) return false;
        }
        return true;
    };
    int apex = -1;
    for (int a = 0; a < n && budget > 0 && apex < 0; ++a)
        if (fans_from(a)) apex = a;
    if (apex < 0 && budget <= 0) {
        budget = budget0;
        for (int a = 0; a < n && budget > 0 && apex < 0; ++a) {
            Vec3 e1 = P(a) - P((a + n - 1) % n), e2 = P((a + 1) % n) - P(a);
            if (dot(cross(e1, e2), nrm) <= 0 && fans_from(a)) apex = a;
        }
    }
    return apex;
}

// Triangulates a simple polygon by clipping ears, O(n^2); `emit_tri(a, b, c)` takes each
// triangle by its corners. What is left of a polygon that is not simple (self-intersecting)
// is fanned from its first remaining corner and counted in `unfanned`.
template <class Corner, class Emit>
void clip_ears(const Corner& P, int n, const Vec3& nrm, const Emit& emit_tri, size_t& unfanned) {
    auto turns_left = [&](const Vec3& a, const Vec3& b, const Vec3& c) { return dot(cross(b - a, c - b), nrm) > 0; };
    auto inside = [&](const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
        return dot(cross(b - a, p - a), nrm) >= 0 && dot(cross(c - b, p - b), nrm) >= 0 && dot(cross(a - c, p - c), nrm) >= 0;
    };
    std::vector<int> ring(static_cast<size_t>(n), 0);
    for (int k = 0; k < n; ++k) ring[size_t(k)] = k;
    size_t i = 0, misses = 0;
    while (ring.size() > 3 && misses < ring.size()) {
        const size_t m = ring.size();
        const int a = ring[(i + m - 1) % m], b = ring[i % m], c = ring[(i + 1) % m];
        const Vec3 pa = P(a), pb = P(b), pc = P(c);
        bool ear = turns_left(pa, pb, pc);
        for (size_t k = 0; ear && k < m; ++k) {
            const int q = ring[k];
            if (q == a || q == b || q == c) continue;
            const Vec3 pq = P(q);
            // Only reflex corners can lie inside an ear of a simple polygon.
            if (!turns_left(P(ring[(k + m - 1) % m]), pq, P(ring[(k + 1) % m])) && inside(pq, pa, pb, pc)) ear = false;
        }
        if (ear) {
            emit_tri(a, b, c);
            ring.erase(ring.begin() + long(i % m));
            misses = 0;
            if (i >= ring.size()) i = 0;
        } else {
            i = (i + 1) % m;
            ++misses;
        }
    }
    if (ring.size() > 3) ++unfanned;  // not a simple polygon (self-intersecting): fan the rest
    for (size_t k = 1; k + 1 < ring.size(); ++k) emit_tri(ring[0], ring[k], ring[k + 1]);
}

// Splits one Blender polygon into convex planar triangles/quads, keeping the corner each
// vertex came from. Quads stay quads only when planar and convex (the quadtree and the
// cubature assume it); other polygons are fanned from a vertex that keeps triangles positive.
void split_polygon(const ObjectDesc& o, int f, double min_area, const Hierarchy& h, std::vector<Primitive>& out,
                   size_t& skipped, size_t& unfanned) {
    const int n = o.loop_totals[f], c0 = o.loop_starts[f];
    auto P = [&](int k) { return h.to_internal(o.vertices[o.corner_verts[c0 + k]]); };
    Vec3 nrm = newell_normal(P, n);
    if (length(nrm) * 0.5 < min_area) { ++skipped; return; }
    nrm = normalize(nrm);
    auto emit_tri = [&](int a, int b, int c) {
        Primitive p;
        p.object = -1;
        p.face = f;
        p.poly.n = 3;
        p.poly.v = {P(a), P(b), P(c), Vec3{}};
        p.corner = {c0 + a, c0 + b, c0 + c, -1};
        if (p.poly.area() < min_area) return;
        out.push_back(p);
    };
    if (n == 4) {
        Poly q;
        q.n = 4;
        q.v = {P(0), P(1), P(2), P(3)};
        if (planar_convex_quad(q, nrm)) {
            Primitive p;
            p.face = f;
            p.poly = q;
            p.corner = {c0, c0 + 1, c0 + 2, c0 + 3};
            out.push_back(p);
            return;
        }
    }
    // Fan from a vertex that sees the whole polygon, if one is found.
    const int apex = fan_apex(P, n, nrm);
    if (apex >= 0) {
        for (int k = 1; k + 1 < n; ++k) emit_tri(apex, (apex + k) % n, (apex + k + 1) % n);
        return;
    }
    // No vertex sees the whole polygon (a U-shaped floor drawn as one n-gon): clip ears. O(n^2),
    // so only up to kMaxEarClip corners; beyond, the fan from corner 0 stands (some pieces face
    // the wrong way) and the solver warns.
    constexpr int kMaxEarClip = 4096;
    if (n > kMaxEarClip) {
        ++unfanned;
        for (int k = 1; k + 1 < n; ++k) emit_tri(0, k, k + 1);
        return;
    }
    clip_ears(P, n, nrm, emit_tri, unfanned);
}

}  // namespace

std::vector<int> Hierarchy::make_prims(const ObjectDesc& o, int oi) {
    const double min_area = 1e-14;
    std::vector<int> ids;
    for (size_t f = 0; f < o.polygon_count(); ++f) {
        const size_t first = prims.size();
        split_polygon(o, int(f), min_area, *this, prims, skipped_polygons, unfanned_polygons);
        for (size_t p = first; p < prims.size(); ++p) {
            prims[p].object = oi;
            prims[p].local = int(ids.size());
            prims[p].poly0 = prims[p].poly;
            prims[p].back = o.two_sided[f] ? -1 : -2;  // -2 marks "no back side"
            ids.push_back(int(p));
        }
    }
    bind_pieces(o, ids);
    return ids;
}

void Hierarchy::bind_pieces(const ObjectDesc& o, const std::vector<int>& ids) {
    prim_pieces.resize(prims.size());
    for (int id : ids) prim_pieces[size_t(id)].clear();
    if (o.pieces.empty()) return;
    // A polygon's primitives in `ids` are consecutive: find each face's range once.
    size_t i = 0;
    while (i < ids.size()) {
        const int face = prims[size_t(ids[i])].face;
        size_t j = i;
        while (j < ids.size() && prims[size_t(ids[j])].face == face) ++j;
        auto lo = std::lower_bound(o.pieces.begin(), o.pieces.end(), face,
                                   [](const TexturePiece& q, int f) { return q.face < f; });
        for (auto it = lo; it != o.pieces.end() && it->face == face; ++it) {
            const Vec3 x = to_internal(it->position);
            // The primitive that holds it (of a fanned n-gon: the piece's triangle), else the
            // nearest; its coordinates in that primitive's own frame.
            int best = -1;
            double best_d = 0;
            for (size_t k = i; k < j; ++k) {
                const Primitive& p = prims[size_t(ids[k])];
                const double d = distance_outside(p.poly0, p.poly0.normal(), x);
                if (best < 0 || d < best_d) best = ids[k], best_d = d;
                if (d <= 0) break;
            }
            const Poly& q = prims[size_t(best)].poly0;
            const Vec3 e1 = q.v[1] - q.v[0], e2 = q.v[size_t(q.n - 1)] - q.v[0], r = x - q.v[0];
            // Least squares in the plane: [e1 e2]^T [e1 e2] (a b)^T = [e1 e2]^T r.
            const double g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2), det = g11 * g22 - g12 * g12;
            if (!(std::fabs(det) > 0)) continue;
            PrimPiece pp;
            pp.a = (g22 * dot(e1, r) - g12 * dot(e2, r)) / det;
            pp.b = (g11 * dot(e2, r) - g12 * dot(e1, r)) / det;
            pp.area = it->area;
            pp.rho = it->rho;
            pp.emission = it->emission;
            pp.emits = o.pieces_emit;
            prim_pieces[size_t(best)].push_back(pp);
        }
        i = j;
    }
}

namespace {
// Where a piece lies: in its primitive's own frame, placed by the primitive's polygon q.
Vec3 piece_position(const Poly& q, const Hierarchy::PrimPiece& pp) {
    return q.v[0] + (q.v[1] - q.v[0]) * pp.a + (q.v[size_t(q.n - 1)] - q.v[0]) * pp.b;
}

const Hierarchy::PrimPiece& nearest_piece(const std::vector<Hierarchy::PrimPiece>& pieces, const Poly& q, const Vec3& x) {
    const Hierarchy::PrimPiece* nearest = &pieces.front();
    double near_d = length(piece_position(q, *nearest) - x);
    for (const Hierarchy::PrimPiece& pp : pieces) {
        const double d = length(piece_position(q, pp) - x);
        if (d < near_d) nearest = &pp, near_d = d;
    }
    return *nearest;
}

// The area mean of `value` over a primitive's pieces inside element e (the nearest piece's
// value when none is inside).
template <class F>
Rgb piece_mean(const Node& e, const std::vector<Hierarchy::PrimPiece>& pieces, const Poly& q, const F& value) {
    Rgb sum;
    double w = 0;
    for (const Hierarchy::PrimPiece& pp : pieces)
        if (distance_outside(e.poly, e.normal, piece_position(q, pp)) <= 0) {
            sum += value(pp) * pp.area;
            w += pp.area;
        }
    return w > 0 ? sum / w : value(nearest_piece(pieces, q, e.center));
}
}  // namespace

int Hierarchy::pieces_prim(const Node& e) const {
    if (e.surface < 0) return -1;
    const int pi = surfaces[size_t(e.surface)].prim;
    return pi >= 0 && size_t(pi) < prim_pieces.size() && !prim_pieces[size_t(pi)].empty() ? pi : -1;
}

Rgb Hierarchy::element_emission(const Node& e, const Rgb& uniform) const {
    const int pi = pieces_prim(e);
    if (pi < 0 || !prim_pieces[size_t(pi)].front().emits) return uniform;
    return piece_mean(e, prim_pieces[size_t(pi)], prims[size_t(pi)].poly,
                      [](const PrimPiece& p) { return p.emission; });
}

Rgb Hierarchy::element_rho(const Node& e, const Rgb& uniform) const {
    const int pi = pieces_prim(e);
    if (pi < 0) return uniform;
    return piece_mean(e, prim_pieces[size_t(pi)], prims[size_t(pi)].poly,
                      [](const PrimPiece& p) { return p.rho; });
}

Rgb Hierarchy::rho_at(int id, const Vec3& x) const {
    const Node& e = nodes[size_t(id)];
    const int pi = pieces_prim(e);
    if (pi < 0) return e.rho;
    return nearest_piece(prim_pieces[size_t(pi)], prims[size_t(pi)].poly, x).rho;
}

void Hierarchy::add_surfaces_of_prims(const std::vector<int>& ids, int begin, int end, int parent) {
    for (int i = begin; i < end; ++i) {
        Primitive& pr = prims[ids[i]];
        for (int side = 0; side < 2; ++side) {
            if (side == 1 && pr.back == -2) continue;  // one-sided polygon
            int s = int(surfaces.size());
            int nid = new_node(NodeKind::Element, parent);
            Node& e = nodes[nid];
            e.object = pr.object;
            e.surface = s;
            e.poly = pr.poly;
            if (side == 1) std::reverse(e.poly.v.begin(), e.poly.v.begin() + e.poly.n);
            e.normal = e.poly.normal();
            e.area = e.poly.area();
            e.center = e.poly.centroid();
            for (int k = 0; k < e.poly.n; ++k) {
                e.box.grow(e.poly.v[k]);
                e.radius = std::max(e.radius, length(e.poly.v[k] - e.center));
            }
            // By object and the primitive's place in it, not by creation order: the same
            // surface gets the same key when other objects are added or removed.
            e.key = mix(mix(0x5EED, object_keys_[pr.object]), uint64_t(2 * pr.local + side));
            surfaces.push_back({nid, ids[i], side == 1});
            surface_order.push_back(s);
            if (side == 0) pr.front = s; else pr.back = s;
        }
    }
}

namespace {
// A cluster's geometry summed over its parts (its surfaces' roots, or its children): area,
// box, facing bins, largest reflectance, then its centre (area-weighted, or its box's when it
// has no area) and radius.
class ClusterSum {
public:
    explicit ClusterSum(Node& c) : c_(c) {
        c_.area = 0;
        c_.box = Aabb{};
        c_.W.fill(0);
    }
    void add(const Node& e) {
        c_.area += e.area;
        acc_ += e.center * e.area;
        c_.box.grow(e.box);
        if (e.is_cluster()) {
            rho_max_ = std::max(rho_max_, e.rho_max);
            for (int b = 0; b < kBins; ++b) c_.W[b] += e.W[b];
            return;
        }
        rho_max_ = std::max(rho_max_, e.rho.max());
        for (int a = 0; a < 3; ++a) {
            const double v = e.normal[a] * e.area;
            c_.W[bin_of(a, v)] += std::fabs(v);
        }
    }
    void finish() {
        c_.rho_max = rho_max_;
        c_.center = c_.area > 0 ? acc_ / c_.area : c_.box.center();
        c_.radius = 0;
        for (int k = 0; k < 8; ++k) {
            Vec3 corner{(k & 1) ? c_.box.hi.x : c_.box.lo.x, (k & 2) ? c_.box.hi.y : c_.box.lo.y,
                        (k & 4) ? c_.box.hi.z : c_.box.lo.z};
            c_.radius = std::max(c_.radius, length(corner - c_.center));
        }
    }

private:
    Node& c_;
    Vec3 acc_;
    double rho_max_ = 0;
};
}  // namespace

void Hierarchy::refresh_cluster_geometry(int id) {
    ClusterSum sum(nodes[id]);
    for (int i = nodes[id].surf_begin; i < nodes[id].surf_end; ++i) sum.add(nodes[surfaces[surface_order[i]].root]);
    sum.finish();
}

void Hierarchy::cluster_geometry_from_children(int id) {
    ClusterSum sum(nodes[id]);
    for (int k : nodes[id].children) sum.add(nodes[k]);
    sum.finish();
}

void Hierarchy::index_emitters() {
    emits_.assign(nodes.size(), 0);
    if (root < 0) return;
    // Post-order over the cluster tree from the root (explicit stack: trees can be deep).
    std::vector<std::pair<int, bool>> stack{{root, false}};
    while (!stack.empty()) {
        const auto [id, expanded] = stack.back();
        stack.pop_back();
        const Node& n = nodes[size_t(id)];
        if (!n.is_cluster()) {
            // An element, and the elements it was split into (links reach those too).
            emits_[size_t(id)] = n.emission.max() > 0 ? kEmitsAny | kEmitsAll : 0;
            for (int c : n.children)
                if (!nodes[size_t(c)].dead) stack.push_back({c, false});
            continue;
        }
        if (!expanded) {
            stack.push_back({id, true});
            for (int c : n.children)
                if (!nodes[size_t(c)].dead) stack.push_back({c, false});
            continue;
        }
        uint8_t f = kEmitsAll;  // an empty cluster: every one of its (no) surfaces emits
        for (int c : n.children) {
            if (nodes[size_t(c)].dead) continue;
            const uint8_t fc = emits_[size_t(c)];
            f = uint8_t((f | (fc & kEmitsAny)) & (~kEmitsAll | (fc & kEmitsAll)));
        }
        emits_[size_t(id)] = f;
    }
}

bool Hierarchy::emits(int node, Unknown unknown, bool all) const {
    if (size_t(node) < emits_.size()) return (emits_[size_t(node)] & (all ? kEmitsAll : kEmitsAny)) != 0;
    if (unknown != Unknown::Look) return unknown == Unknown::Emits;
    const Node& n = nodes[size_t(node)];
    if (!n.is_cluster()) return n.emission.max() > 0;
    for (int k = n.surf_begin; k < n.surf_end; ++k) {
        const bool e = nodes[size_t(surfaces[size_t(surface_order[size_t(k)])].root)].emission.max() > 0;
        if (e != all) return e;
    }
    return all;
}

void Hierarchy::finish_cluster(int id) {
    nodes[id].surf_end = int(surface_order.size());
    refresh_cluster_geometry(id);
}

int Hierarchy::build_object_tree(std::vector<int>& ids, int begin, int end, int parent, int object, uint64_t key) {
    int id = new_node(NodeKind::Cluster, parent);
    nodes[id].object = object;
    nodes[id].key = key;
    nodes[id].surf_begin = int(surface_order.size());
    if (end - begin <= 4) {
        add_surfaces_of_prims(ids, begin, end, id);
    } else {
        // Median split along the widest axis of the centroids: a balanced spatial tree gives
        // O(n log n) linking from the root down. The tree must not depend on where the object
        // stands: an update moves an object's tree, a full solve builds it where it now is, and
        // different trees make different cluster links (a box's top refined elsewhere, so an
        // update would differ from a full solve). Rounding makes equal extents (a square box)
        // and equal centroids (a grid's rows) compare differently at two places, so extents
        // within a relative 1e-9 count as equal (the lower axis wins) and centroids are
        // compared on a grid of 2^-30 of the extent, from the low side, ties by polygon order.
        Aabb b;
        for (int i = begin; i < end; ++i) b.grow(prims[ids[i]].poly.centroid());
        const Vec3 ext = b.extent();
        const double widest = std::max({ext.x, ext.y, ext.z});
        int axis = 0;
        while (axis < 2 && ext[axis] < widest * (1.0 - 1e-9)) ++axis;
        const double lo = b.lo[axis], scale = ext[axis] > 0 ? std::ldexp(1.0, 30) / ext[axis] : 0.0;
        std::vector<std::pair<int64_t, int>> order(size_t(end - begin));
        for (int i = begin; i < end; ++i)
            order[size_t(i - begin)] = {std::llround((prims[ids[i]].poly.centroid()[axis] - lo) * scale), ids[i]};
        const int mid = (begin + end) / 2;
        std::nth_element(order.begin(), order.begin() + (mid - begin), order.end());
        for (int i = begin; i < end; ++i) ids[i] = order[size_t(i - begin)].second;
        build_object_tree(ids, begin, mid, id, object, mix(key, 1));
        build_object_tree(ids, mid, end, id, object, mix(key, 2));
    }
    finish_cluster(id);
    return id;
}

void Hierarchy::build(const SceneDesc& scene, bool use_clustering) {
    *this = Hierarchy{};
    const auto& objs = scene.objects();
    Aabb world;
    // Only vertices that polygons use: a stray loose vertex far away (common in real meshes)
    // would otherwise set the frame, and the scene, shrunk to a speck of it, would lose
    // precision (a vertex 1e6 away) or snap to nothing (1e12 away: every polygon skipped).
    for (const auto& o : objs)
        for (int32_t c : o.corner_verts) world.grow(o.vertices[c]);
    if (!world.empty() && world.diagonal() > 0) {
        origin = world.center();
        unit = world.diagonal();
    }

    // Primitives, with the material of their polygon.
    object_keys_.resize(objs.size());
    {
        // name -> earlier objects of that name (empty ones, like removed objects' slots, not
        // counted: they make no node)
        std::map<std::string, int> seen;
        for (size_t oi = 0; oi < objs.size(); ++oi)
            object_keys_[oi] = mix(name_hash(objs[oi].name), uint64_t(objs[oi].polygon_count() ? seen[objs[oi].name]++ : 0));
    }
    std::vector<std::vector<int>> prims_of(objs.size());
    for (size_t oi = 0; oi < objs.size(); ++oi) {
        prims_of[oi] = make_prims(objs[oi], int(oi));
        for (int p : prims_of[oi])
            for (int k = 0; k < prims[p].poly.n; ++k) scene_box.grow(prims[p].poly.v[k]);
    }
    scene_diag = scene_box.empty() ? 1.0 : std::max(scene_box.diagonal(), 1e-300);
    object_node.assign(objs.size(), -1);
    object_of_env.assign(objs.size(), 0);
    object_occludes.assign(objs.size(), 1);
    for (size_t oi = 0; oi < objs.size(); ++oi) {
        object_of_env[oi] = objs[oi].cluster < 0;
        object_occludes[oi] = objs[oi].occluder;
    }
    cluster_node.assign(scene.clusters().size(), -1);

    root = new_node(NodeKind::Cluster, -1);
    nodes[root].surf_begin = 0;
    if (!use_clustering) {
        std::vector<int> all;
        for (auto& v : prims_of) all.insert(all.end(), v.begin(), v.end());
        add_surfaces_of_prims(all, 0, int(all.size()), root);
    } else {
        build_collection_tree(scene, prims_of);
    }
    // Materials of the surface roots.
    for (size_t s = 0; s < surfaces.size(); ++s) set_surface_material(scene, int(s));
    finish_cluster(root);
    // Cluster rho_max needs the materials: recompute every cluster once.
    for (size_t i = 0; i < nodes.size(); ++i)
        if (nodes[i].is_cluster()) refresh_cluster_geometry(int(i));
    surface_ancestors_.assign(surfaces.size(), {});
    for (size_t s = 0; s < surfaces.size(); ++s) set_surface_ancestors(int(s));
    refresh_surface_geom();
}

// The collection clusters that hold any primitive, each with its sub-collections and then its
// objects' trees, under the root, followed by the trees of the objects in no collection.
void Hierarchy::build_collection_tree(const SceneDesc& scene, std::vector<std::vector<int>>& prims_of) {
    const auto& objs = scene.objects();
    const auto& cl = scene.clusters();
    std::vector<std::vector<int>> sub(cl.size()), objs_in(cl.size());
    std::vector<int> top_clusters, top_objects;
    for (size_t c = 0; c < cl.size(); ++c)
        (cl[c].parent < 0 ? top_clusters : sub[cl[c].parent]).push_back(int(c));
    for (size_t oi = 0; oi < objs.size(); ++oi)
        (objs[oi].cluster < 0 ? top_objects : objs_in[objs[oi].cluster]).push_back(int(oi));
    std::vector<char> nonempty(cl.size(), 0);
    for (int c = int(cl.size()) - 1; c >= 0; --c) {  // parents precede children
        for (int oi : objs_in[c]) nonempty[c] |= !prims_of[oi].empty();
        for (int s : sub[c]) nonempty[c] |= nonempty[s];
    }
    auto build_objects = [&](const std::vector<int>& list, int parent) {
        for (int oi : list)
            if (!prims_of[oi].empty())
                object_node[oi] = build_object_tree(prims_of[oi], 0, int(prims_of[oi].size()), parent, oi,
                                                    object_tree_key(object_keys_[oi]));
    };
    std::function<void(int, int)> build_cluster = [&](int c, int parent) {
        int id = new_node(NodeKind::Cluster, parent);
        cluster_node[c] = id;
        nodes[id].surf_begin = int(surface_order.size());
        for (int s : sub[c])
            if (nonempty[s]) build_cluster(s, id);
        build_objects(objs_in[c], id);
        nodes[id].key = collection_key(scene, c);
        finish_cluster(id);
    };
    for (int c : top_clusters)
        if (nonempty[c]) build_cluster(c, root);
    build_objects(top_objects, root);
}

void Hierarchy::set_surface_material(const SceneDesc& scene, int s) {
    Node& e = nodes[surfaces[s].root];
    const Primitive& p = prims[surfaces[s].prim];
    e.rho = element_rho(e, scene.objects()[p.object].reflectance[p.face]);
    e.emission = element_emission(e, scene.objects()[p.object].emission[p.face]);
    e.L = e.emission;
    e.Lmin = e.Lmax = e.L;
}

void Hierarchy::apply_materials(const SceneDesc& scene) {
    for (const Primitive& p : prims) {
        if (p.object < 0) continue;  // of a removed object
        const ObjectDesc& o = scene.objects()[p.object];
        for (int s : {p.front, p.back}) {
            if (s < 0) continue;
            std::vector<int> st{surfaces[s].root};
            while (!st.empty()) {
                Node& n = nodes[st.back()];
                st.pop_back();
                n.rho = element_rho(n, o.reflectance[p.face]);
                n.emission = element_emission(n, o.emission[p.face]);
                for (int c : n.children) st.push_back(c);
            }
        }
    }
    // Each cluster from its surfaces' roots (its largest reflectance among them).
    for (int i = int(nodes.size()) - 1; i >= 0; --i)
        if (nodes[i].is_cluster()) refresh_cluster_geometry(i);
}

Hierarchy::SurfaceTotals Hierarchy::surface_totals() const {
    SurfaceTotals t;
    for (const Surface& s : surfaces) {
        const Node& e = nodes[s.root];
        if (e.dead) continue;  // of a removed object
        t.emission += e.area * e.emission.max();
        t.reflectance += e.area * e.rho.max();
        t.area += e.area;
    }
    return t;
}

void Hierarchy::set_surface_ancestors(int s) {
    if (int(surface_ancestors_.size()) <= s) surface_ancestors_.resize(s + 1);
    std::vector<int> chain;
    for (int p = nodes[surfaces[s].root].parent; p >= 0; p = nodes[p].parent) chain.push_back(p);
    std::reverse(chain.begin(), chain.end());
    surface_ancestors_[s] = std::move(chain);
}

void Hierarchy::subdivide(int id) {
    if (!nodes[id].children.empty() || nodes[id].is_cluster()) return;
    for (int k = 0; k < 4; ++k) {
        int c = new_node(NodeKind::Element, id);
        Node& p = nodes[id];
        Node& e = nodes[c];
        e.object = p.object;
        e.surface = p.surface;
        e.depth = p.depth + 1;
        e.poly = p.poly.child(k);
        e.normal = p.normal;
        e.area = e.poly.area();
        e.center = e.poly.centroid();
        for (int i = 0; i < e.poly.n; ++i) {
            e.box.grow(e.poly.v[i]);
            e.radius = std::max(e.radius, length(e.poly.v[i] - e.center));
        }
        e.rho = element_rho(e, p.rho);
        e.emission = element_emission(e, p.emission);
        e.L = p.L;
        // A textured emitter's child emits its own part: its radiance swaps the emission.
        if (!(e.emission.r == p.emission.r && e.emission.g == p.emission.g && e.emission.b == p.emission.b))
            e.L = cmax(p.L - p.emission, Rgb{}) + e.emission;
        e.Lmin = e.Lmax = e.L;
        e.pocket = p.pocket;
        e.key = mix(p.key, uint64_t(k + 1));
    }
}

uint64_t Hierarchy::mix(uint64_t a, uint64_t b) {
    uint64_t z = a * 0x9E3779B97F4A7C15ull + b + 0x632BE59BD9B4E019ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

std::vector<int> Hierarchy::object_nodes(int object) const {
    std::vector<int> out, stack;
    if (object_node[object] >= 0) {
        stack.push_back(object_node[object]);
    } else {
        for (const Primitive& p : prims)
            if (p.object == object) {
                if (p.front >= 0) stack.push_back(surfaces[p.front].root);
                if (p.back >= 0) stack.push_back(surfaces[p.back].root);
            }
    }
    while (!stack.empty()) {
        int id = stack.back();
        stack.pop_back();
        out.push_back(id);
        for (int c : nodes[id].children) stack.push_back(c);
    }
    return out;
}

std::vector<std::vector<int>> Hierarchy::object_cluster_levels(int object) const {
    std::vector<std::vector<int>> levels;
    const int top = object_node[size_t(object)];
    if (top < 0 || !nodes[size_t(top)].is_cluster()) return levels;
    levels.push_back({top});
    for (;;) {
        std::vector<int> next;
        for (int id : levels.back())
            for (int c : nodes[size_t(id)].children)
                if (nodes[size_t(c)].is_cluster()) next.push_back(c);
        if (next.empty()) return levels;
        levels.push_back(std::move(next));
    }
}

std::vector<int> Hierarchy::clusters_above(int object) const {
    std::vector<int> up;
    const int top = object_node[size_t(object)];
    for (int a = top >= 0 ? nodes[size_t(top)].parent : root; a >= 0; a = nodes[size_t(a)].parent) up.push_back(a);
    return up;
}

double Hierarchy::tables_bytes() const {
    double b = held_bytes(prims) + held_bytes(prim_pieces) + held_bytes(surfaces) + held_bytes(surface_order) +
               held_bytes(surface_geom) + held_bytes(area_prefix) + held_bytes(sampler_records) +
               held_bytes(sampler_first) + held_bytes(pocket_sets) + held_bytes(object_node) + held_bytes(cluster_node) +
               held_bytes(object_of_env) + held_bytes(object_occludes) + held_bytes(emits_) +
               held_bytes(surface_ancestors_) + held_bytes(object_keys_) + held_bytes(facing_summary);
    for (const FacingSummary& f : facing_summary) b += held_bytes(f.groups);
    return b;
}

Aabb Hierarchy::object_box(int object, const std::vector<int>* own) const {
    Aabb b;
    auto take = [&](const Primitive& p) {
        if (p.object == object)
            for (int k = 0; k < p.poly.n; ++k) b.grow(p.poly.v[k]);
    };
    if (own)
        for (int i : *own) take(prims[size_t(i)]);
    else
        for (const Primitive& p : prims) take(p);
    return b;
}

namespace {
// Re-derives an element's geometry from its polygon, and its children's from theirs.
void set_element_poly(Hierarchy& h, int id, const Poly& poly) {
    Node& e = h.nodes[id];
    e.poly = poly;
    e.normal = poly.normal();
    e.center = poly.centroid();
    e.box = Aabb{};
    e.radius = 0;
    for (int k = 0; k < poly.n; ++k) {
        e.box.grow(poly.v[k]);
        e.radius = std::max(e.radius, length(poly.v[k] - e.center));
    }
    // (By index: the children's own calls leave this node's list as it is.)
    for (size_t k = 0; k < h.nodes[id].children.size(); ++k) set_element_poly(h, h.nodes[id].children[k], poly.child(int(k)));
}
}  // namespace

}  // namespace radiosity

namespace radiosity {

uint64_t Hierarchy::object_key(const SceneDesc& scene, int object) {
    const auto& objs = scene.objects();
    uint64_t same = 0;
    for (int o = 0; o < object; ++o) same += objs[o].polygon_count() > 0 && objs[o].name == objs[object].name;
    return mix(name_hash(objs[object].name), same);
}

int Hierarchy::ensure_cluster_node(const SceneDesc& scene, int c) {
    if (cluster_node[c] >= 0) return cluster_node[c];
    const int pc = scene.clusters()[c].parent;
    const int parent = pc < 0 ? root : ensure_cluster_node(scene, pc);
    const int id = new_node(NodeKind::Cluster, parent);
    nodes[id].key = collection_key(scene, c);
    cluster_node[c] = id;
    // A fresh build lists a node's collection children (by index: this one is the newest)
    // before its object children; the order matters because surface_order follows it.
    std::vector<int>& kids = nodes[parent].children;
    kids.pop_back();
    auto first_object = std::find_if(kids.begin(), kids.end(), [this](int k) { return nodes[k].object >= 0; });
    kids.insert(first_object, id);
    return id;
}

namespace {
// One facing group: the same pocket and bit-equal normals.
bool same_facing(int pa, const Vec3& na, int pb, const Vec3& nb) {
    return pa == pb && na.x == nb.x && na.y == nb.y && na.z == nb.z;
}

// The summary of surfaces [b, e), or none when they have too many normals or pockets.
Hierarchy::FacingSummary summarise(const std::vector<SurfaceGeom>& g, int b, int e) {
    Hierarchy::FacingSummary f;
    for (int i = b; i < e; ++i) {
        const SurfaceGeom& s = g[size_t(i)];
        bool found = false;
        for (auto& grp : f.groups)
            if (same_facing(grp.pocket, grp.normal, s.pocket, s.normal)) {
                grp.area += s.area;
                found = true;
                break;
            }
        if (!found) {
            if (int(f.groups.size()) >= Hierarchy::kSummaryMaxNormals) return Hierarchy::FacingSummary{};
            f.groups.push_back({s.normal, s.pocket, s.area});
        }
    }
    f.valid = e > b;
    return f;
}
}  // namespace

namespace {
// A sampler record's facing data from its node: area, and a cluster's bins or a surface
// root's normal.
void take_facing(Hierarchy::SamplerRecord& sc, const Node& m) {
    sc.area = m.area;
    if (sc.cluster) sc.W = m.W;
    else sc.W = {m.normal.x, m.normal.y, m.normal.z, 0.0, 0.0, 0.0};
}

// A surface's geometry from its root node.
void take_geometry(SurfaceGeom& g, const Node& e) {
    g.poly = e.poly;
    g.normal = e.normal;
    g.area = e.area;
    g.share = e.poly.first_share();
}

// Node n's facing summary: none unless it is a live cluster of enough surfaces.
Hierarchy::FacingSummary summary_of(const std::vector<SurfaceGeom>& g, const Node& n) {
    if (!n.is_cluster() || n.dead || n.surf_end - n.surf_begin < Hierarchy::kSummaryMinSurfaces) return {};
    return summarise(g, n.surf_begin, n.surf_end);
}

// The nodes a sampler draws among below cluster n (Hierarchy::kSamplerFanOut): its children,
// with live clusters among them replaced by their own children, in order, level after level,
// while the list stays within the fan-out. They hold n's surfaces once each, as its children do.
void sampler_entries(const Hierarchy& h, const Node& n, std::vector<int>& out, std::vector<int>& next) {
    out.assign(n.children.begin(), n.children.end());
    for (bool grew = true; grew;) {
        grew = false;
        next.clear();
        size_t room = Hierarchy::kSamplerFanOut > out.size() ? Hierarchy::kSamplerFanOut - out.size() : 0;
        for (int c : out) {
            const Node& m = h.nodes[size_t(c)];
            if (m.is_cluster() && !m.dead && !m.children.empty() && m.children.size() - 1 <= room) {
                room -= m.children.size() - 1;
                next.insert(next.end(), m.children.begin(), m.children.end());
                grew = true;
            } else {
                next.push_back(c);
            }
        }
        out.swap(next);
    }
}

// The samplers' copy of the cluster tree (Hierarchy::sampler_records): per cluster, in
// node order, the nodes sampler_entries() gives, in their order.
void sampler_tree(const Hierarchy& h, std::vector<Hierarchy::SamplerRecord>& children, std::vector<int>& first) {
    children.clear();
    first.assign(h.nodes.size() + 1, 0);
    std::vector<int> geom_of(h.surfaces.size(), -1);
    for (size_t i = 0; i < h.surface_order.size(); ++i) geom_of[size_t(h.surface_order[i])] = int(i);
    std::vector<int> entries, scratch;
    for (size_t id = 0; id < h.nodes.size(); ++id) {
        first[id] = int(children.size());
        const Node& n = h.nodes[id];
        if (!n.is_cluster()) continue;
        sampler_entries(h, n, entries, scratch);
        for (int c : entries) {
            const Node& m = h.nodes[size_t(c)];
            Hierarchy::SamplerRecord sc;
            sc.id = c;
            sc.cluster = m.is_cluster();
            sc.dead = m.dead;
            take_facing(sc, m);
            if (!sc.cluster) {
                sc.pocket = m.pocket;
                sc.geom = m.surface >= 0 ? geom_of[size_t(m.surface)] : -1;
            }
            children.push_back(sc);
        }
    }
    first[h.nodes.size()] = int(children.size());
    for (Hierarchy::SamplerRecord& sc : children)
        if (sc.cluster) sc.first = first[size_t(sc.id)], sc.count = first[size_t(sc.id) + 1] - sc.first;
}
}  // namespace

void Hierarchy::refresh_surface_geom() {
    surface_geom.resize(surface_order.size());
    for (size_t i = 0; i < surface_order.size(); ++i) {
        const int r = surfaces[surface_order[i]].root;
        const Node& e = nodes[r];
        SurfaceGeom& g = surface_geom[i];
        take_geometry(g, e);
        g.root = r;
        g.object = e.object;
        g.pocket = e.pocket;
    }
    area_prefix.assign(surface_geom.size() + 1, 0.0);
    for (size_t i = 0; i < surface_geom.size(); ++i) area_prefix[i + 1] = area_prefix[i] + surface_geom[i].area;
    facing_summary.assign(nodes.size(), FacingSummary{});
    for (size_t id = 0; id < nodes.size(); ++id) facing_summary[id] = summary_of(surface_geom, nodes[id]);
    sampler_tree(*this, sampler_records, sampler_first);  // after the clusters' geometry
}

void Hierarchy::refresh_surface_tables(std::vector<std::pair<int, int>> ranges, const std::vector<int>& changed) {
    // The prefix summed afresh within each range; past it, shifted by what the range's sum
    // changed (a rigid placement changes areas by rounding alone): no read of the other
    // surfaces' geometry.
    std::sort(ranges.begin(), ranges.end());
    double shift = 0;
    size_t at = 0;
    auto shift_to = [&](size_t end) {
        if (shift != 0)
            for (size_t i = at; i < end; ++i) area_prefix[i + 1] += shift;
        at = std::max(at, end);
    };
    for (const auto& [b, e] : ranges) {
        shift_to(size_t(b));
        const double was = area_prefix[size_t(e)];
        for (size_t i = std::max(at, size_t(b)); i < size_t(e); ++i) area_prefix[i + 1] = area_prefix[i] + surface_geom[i].area;
        shift = area_prefix[size_t(e)] - was;
        at = std::max(at, size_t(e));
    }
    shift_to(surface_geom.size());
    for (int id : changed) {
        facing_summary[size_t(id)] = summary_of(surface_geom, nodes[size_t(id)]);
        for (int k = sampler_first[size_t(id)]; k < sampler_first[size_t(id) + 1]; ++k)
            take_facing(sampler_records[size_t(k)], nodes[size_t(sampler_records[size_t(k)].id)]);
    }
}

void Hierarchy::place_objects(const std::vector<std::pair<int, Rigid>>& placed, bool whole,
                              const std::vector<std::vector<int>>* own, int threads) {
    if (placed.empty()) return;
    std::vector<int> changed;  // (a partial refresh) clusters whose geometry changed
    std::vector<std::pair<int, int>> ranges;  // ... and the surface-table ranges
    for (size_t j = 0; j < placed.size(); ++j) {
        const int object = placed[j].first;
        const Rigid& placement = placed[j].second;
        auto place = [&](Primitive& p) {
            for (int k = 0; k < p.poly.n; ++k) p.poly.v[k] = placement.point(p.poly0.v[k]);
            if (p.front >= 0) set_element_poly(*this, surfaces[p.front].root, p.poly);
            if (p.back >= 0) {
                Poly b = p.poly;
                std::reverse(b.v.begin(), b.v.begin() + b.n);
                set_element_poly(*this, surfaces[p.back].root, b);
            }
        };
        if (own) {
            const std::vector<int>& mine = (*own)[j];
            parallel_for(mine.size(), threads, [&](size_t k) {
                if (prims[size_t(mine[k])].object == object) place(prims[size_t(mine[k])]);
            }, 256);
        } else {
            for (Primitive& p : prims)
                if (p.object == object) place(p);
        }
        // Clusters of the object, then every cluster above it.
        const int top = object_node[object];
        whole = whole || top < 0 || !nodes[top].is_cluster();
        const std::vector<std::vector<int>> levels = object_cluster_levels(object);
        const std::vector<int> up = clusters_above(object);
        if (whole) {
            for (const std::vector<int>& level : levels)
                for (int id : level) refresh_cluster_geometry(id);
            for (int a : up) refresh_cluster_geometry(a);
            continue;
        }
        // From the deepest level up, each level in parallel: a cluster's geometry is its
        // children's, made before it.
        for (auto level = levels.rbegin(); level != levels.rend(); ++level)
            parallel_for(level->size(), threads, [&](size_t k) { cluster_geometry_from_children((*level)[k]); }, 16);
        for (int a : up) cluster_geometry_from_children(a);
        const Node& t = nodes[top];
        for (int i = t.surf_begin; i < t.surf_end; ++i)
            take_geometry(surface_geom[size_t(i)], nodes[surfaces[surface_order[size_t(i)]].root]);
        ranges.emplace_back(t.surf_begin, t.surf_end);
        for (const std::vector<int>& level : levels) changed.insert(changed.end(), level.begin(), level.end());
        changed.insert(changed.end(), up.begin(), up.end());
    }
    if (whole) {
        refresh_surface_geom();
        return;
    }
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
    refresh_surface_tables(ranges, changed);
}

bool Hierarchy::surface_geom_current() const {
    if (surface_geom.size() != surface_order.size()) return false;
    for (size_t i = 0; i < surface_order.size(); ++i) {
        const int r = surfaces[surface_order[i]].root;
        const Node& e = nodes[r];
        const SurfaceGeom& g = surface_geom[i];
        if (g.root != r || g.object != e.object || g.pocket != e.pocket || g.area != e.area || g.poly.n != e.poly.n)
            return false;
        for (int k = 0; k < e.poly.n; ++k)
            if (g.poly.v[k].x != e.poly.v[k].x || g.poly.v[k].y != e.poly.v[k].y || g.poly.v[k].z != e.poly.v[k].z)
                return false;
    }
    // The samplers' summaries: the prefix sums and each cluster's groups as a fresh scan makes them.
    // Nodes made since the last refresh are elements (splits), which have no summary.
    if (area_prefix.size() != surface_geom.size() + 1 || facing_summary.size() > nodes.size()) return false;
    for (size_t i = 0; i < surface_geom.size(); ++i)
        if (area_prefix[i + 1] != area_prefix[i] + surface_geom[i].area) return false;
    for (size_t id = 0; id < nodes.size(); ++id) {
        const FacingSummary fresh = summary_of(surface_geom, nodes[id]);
        const FacingSummary none;
        const FacingSummary& got = id < facing_summary.size() ? facing_summary[id] : none;
        if (got.valid != fresh.valid || got.groups.size() != fresh.groups.size()) return false;
        for (size_t k = 0; k < got.groups.size(); ++k) {
            const FacingGroup &a = got.groups[k], &b = fresh.groups[k];
            if (!same_facing(a.pocket, a.normal, b.pocket, b.normal) || a.area != b.area) return false;
        }
    }
    // The samplers' tree: clusters are made and changed only where surface_geom is refreshed.
    std::vector<SamplerRecord> children;
    std::vector<int> first;
    sampler_tree(*this, children, first);
    for (size_t id = 0; id < nodes.size(); ++id) {
        if (!nodes[id].is_cluster()) continue;
        if (id + 1 >= sampler_first.size() || first[id + 1] - first[id] != sampler_first[id + 1] - sampler_first[id])
            return false;
        for (int k = 0; k < first[id + 1] - first[id]; ++k) {
            const SamplerRecord& a = children[size_t(first[id] + k)];
            const SamplerRecord& b = sampler_records[size_t(sampler_first[id] + k)];
            if (a.id != b.id || a.cluster != b.cluster || a.dead != b.dead || a.pocket != b.pocket || a.geom != b.geom ||
                a.first != b.first || a.count != b.count || a.area != b.area || a.W != b.W)
                return false;
        }
    }
    return true;
}

void Hierarchy::rebuild_surface_order() {
    surface_order.clear();
    std::function<void(int)> walk = [&](int id) {
        Node& n = nodes[id];
        if (!n.is_cluster()) {
            surface_order.push_back(n.surface);
            return;
        }
        n.surf_begin = int(surface_order.size());
        for (int c : n.children) walk(c);
        n.surf_end = int(surface_order.size());
    };
    walk(root);
}

void Hierarchy::set_pocket_sets() {
    pocket_sets.clear();
    for (size_t id = 0; id < nodes.size(); ++id) {
        Node& c = nodes[id];
        if (!c.is_cluster()) continue;
        c.pocket_set = -1;
        if (c.dead) continue;
        std::vector<int> v;
        for (int i = c.surf_begin; i < c.surf_end; ++i) v.push_back(nodes[size_t(surfaces[size_t(surface_order[size_t(i)])].root)].pocket);
        std::sort(v.begin(), v.end());
        v.erase(std::unique(v.begin(), v.end()), v.end());
        c.pocket_set = int(pocket_sets.size());
        pocket_sets.push_back(std::move(v));
    }
}

int Hierarchy::leaf_at(int id, const Vec3& x) const {
    // Children are Poly::child(0..3) of their parent, in that order (subdivide). A quad splits
    // along its two midlines (joining opposite edge midpoints, through the centre), a triangle
    // along the three lines joining its edge midpoints, so a few side tests against the
    // parent's own corners name the child: one node read per level instead of four, and no
    // distance to four polygons (comparing those was a quarter of a link evaluation's time,
    // for its samples). A side test that is NaN or 0 counts as "not on the corner's side".
    while (!nodes[size_t(id)].children.empty()) {
        const Node& p = nodes[size_t(id)];
        // The next level reads one of the children: fetch all four while this one decides.
        for (int c : p.children) {
            __builtin_prefetch(&nodes[size_t(c)].children);
            __builtin_prefetch(&nodes[size_t(c)].poly.v[2]);
        }
        const Vec3* v = p.poly.v.data();
        // Whether x is on the same side as corner c of the line a-b, in the polygon's plane.
        auto with = [&](const Vec3& c, const Vec3& a, const Vec3& b) {
            const Vec3 ab = b - a;
            return dot(cross(ab, x - a), p.normal) * dot(cross(ab, c - a), p.normal) > 0;
        };
        int k;
        if (p.poly.n == 3) {
            const Vec3 m01 = (v[0] + v[1]) * 0.5, m12 = (v[1] + v[2]) * 0.5, m20 = (v[2] + v[0]) * 0.5;
            k = with(v[0], m01, m20) ? 0 : with(v[1], m01, m12) ? 1 : with(v[2], m12, m20) ? 2 : 3;
        } else {
            const Vec3 m0 = (v[0] + v[1]) * 0.5, m1 = (v[1] + v[2]) * 0.5, m2 = (v[2] + v[3]) * 0.5,
                       m3 = (v[3] + v[0]) * 0.5;
            const bool a = with(v[0], m0, m2);  // children 0 and 3
            const bool b = with(v[0], m3, m1);  // children 0 and 1
            k = a ? (b ? 0 : 3) : (b ? 1 : 2);
        }
        id = p.children[size_t(k)];
    }
    return id;
}

bool Hierarchy::share_pocket(int a, int b) const {
    const Node& na = nodes[size_t(a)];
    const Node& nb = nodes[size_t(b)];
    if (!na.is_cluster()) return holds_pocket(b, na.pocket);
    if (!nb.is_cluster()) return holds_pocket(a, nb.pocket);
    if (na.pocket_set < 0 || nb.pocket_set < 0) return false;
    const std::vector<int>& u = pocket_sets[size_t(na.pocket_set)];
    const std::vector<int>& v = pocket_sets[size_t(nb.pocket_set)];
    for (size_t i = 0, j = 0; i < u.size() && j < v.size();) {  // both sorted
        if (u[i] == v[j]) return true;
        if (u[i] < v[j]) ++i;
        else ++j;
    }
    return false;
}

int Hierarchy::add_object(const SceneDesc& scene, int oi, bool use_clustering) {
    const ObjectDesc& o = scene.objects()[oi];
    const size_t no = scene.objects().size();
    object_node.resize(no, -1);
    object_of_env.resize(no, 0);
    object_of_env[oi] = o.cluster < 0;
    object_occludes.resize(no, 1);
    object_occludes[size_t(oi)] = o.occluder;
    cluster_node.resize(scene.clusters().size(), -1);
    object_keys_.resize(no, 0);
    object_keys_[oi] = object_key(scene, oi);
    const size_t first_node = nodes.size(), first_surface = surfaces.size();
    std::vector<int> ids = make_prims(o, oi);
    if (ids.empty()) return -1;  // every polygon of zero area: nothing to place
    int top = -1;
    if (!use_clustering) {
        add_surfaces_of_prims(ids, 0, int(ids.size()), root);
    } else {
        // Objects follow collections among a node's children, in object order: the new one,
        // having the highest id, goes last, where a fresh build puts it.
        const int parent = o.cluster < 0 ? root : ensure_cluster_node(scene, o.cluster);
        object_node[oi] = build_object_tree(ids, 0, int(ids.size()), parent, oi, object_tree_key(object_keys_[oi]));
        top = object_node[oi];
        while (nodes[top].parent != root && size_t(nodes[top].parent) >= first_node) top = nodes[top].parent;
    }
    for (size_t s = first_surface; s < surfaces.size(); ++s) {
        set_surface_material(scene, int(s));
        set_surface_ancestors(int(s));
    }
    rebuild_surface_order();
    // New clusters bottom-up (children have larger ids), then the existing ones above them.
    for (size_t id = nodes.size(); id-- > first_node;)
        if (nodes[id].is_cluster()) refresh_cluster_geometry(int(id));
    const int above = top >= 0 ? nodes[top].parent : root;
    for (int a = above; a >= 0; a = nodes[a].parent) refresh_cluster_geometry(a);
    refresh_surface_geom();  // its samplers' tree reads the clusters' areas and facing bins
    return top;
}

Hierarchy::Removed Hierarchy::remove_object(int oi) {
    const std::vector<int> ids = object_nodes(oi);
    auto detach = [this](int id) {
        std::vector<int>& kids = nodes[nodes[id].parent].children;
        kids.erase(std::remove(kids.begin(), kids.end(), id), kids.end());
    };
    int deepest = root;
    if (object_node[oi] >= 0) {
        const int top = object_node[oi];
        deepest = nodes[top].parent;
        detach(top);
        // Collection clusters left without any node go as well.
        while (deepest != root && nodes[deepest].children.empty()) {
            const int dead = deepest;
            deepest = nodes[dead].parent;
            detach(dead);
            nodes[dead].dead = true;
            for (int& c : cluster_node)
                if (c == dead) c = -1;
        }
        object_node[oi] = -1;
    } else {
        for (int id : ids)
            if (nodes[id].parent == root) detach(id);
    }
    int elements = 0;
    for (int id : ids) {
        elements += retire(id);
        nodes[id].pocket = 0;
        nodes[id].pocket_set = -1;
    }
    for (Primitive& p : prims)
        if (p.object == oi) p.object = -1;
    rebuild_surface_order();
    for (int a = deepest; a >= 0; a = nodes[a].parent) refresh_cluster_geometry(a);
    refresh_surface_geom();  // its samplers' tree reads the clusters' areas and facing bins
    return {deepest, elements};
}

int Hierarchy::retire(int id) {
    Node& n = nodes[size_t(id)];
    n.dead = true;
    std::vector<int>().swap(n.in_links);
    std::vector<int>().swap(n.out_links);
    return n.is_cluster() ? 0 : 1;
}

int Hierarchy::retire_below(int id) {
    int retired = 0;
    std::vector<int> stack(nodes[size_t(id)].children.begin(), nodes[size_t(id)].children.end());
    while (!stack.empty()) {
        const int c = stack.back();
        stack.pop_back();
        std::vector<int>& kids = nodes[size_t(c)].children;
        stack.insert(stack.end(), kids.begin(), kids.end());
        kids.clear();
        retired += retire(c);
    }
    nodes[size_t(id)].children.clear();
    return retired;
}

int Hierarchy::side_met(int prim, const Vec3& d) const {
    const Primitive& p = prims[size_t(prim)];
    const Vec3 fn = p.front >= 0 ? nodes[size_t(surfaces[size_t(p.front)].root)].normal : p.poly.normal();
    const int side = dot(d, fn) < 0 ? p.front : p.back;
    return side >= 0 && !surface_dead(side) ? side : -1;
}

}  // namespace radiosity
