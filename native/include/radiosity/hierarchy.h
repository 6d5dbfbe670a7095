// The node hierarchy of clustering-based hierarchical radiosity (paper 3.1):
// root cluster -> collection clusters -> object clusters -> automatic spatial sub-clusters
// -> oriented surfaces (one per side of an input polygon) -> element quadtrees.
// Hierarchy owns that tree and the geometry it is made of (primitives, surfaces, texture
// pieces): it builds them from a SceneDesc and keeps them consistent as elements split and
// are retired, and as objects move, come and go. It sets its nodes' materials (reflectance,
// emission) from the scene; their radiance fields are the solver's to write.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "radiosity/chunked.h"
#include "radiosity/geometry.h"
#include "radiosity/rigid.h"
#include "radiosity/scene.h"
#include "radiosity/vec.h"

namespace radiosity {

enum class NodeKind : uint8_t { Cluster, Element };

// Six signed axis bins (+x,-x,+y,-y,+z,-z): clusters keep per-bin projected area and
// radiance x projected area so a sender cluster's directional radiance is cheap to estimate.
constexpr int kBins = 6;
inline int bin_of(int axis, double sign) { return axis * 2 + (sign < 0 ? 1 : 0); }

struct Node {
    NodeKind kind = NodeKind::Element;
    int parent = -1;
    std::vector<int> children;
    int object = -1;   // owning object; -1 above object level
    int surface = -1;  // elements: oriented surface index
    int depth = 0;     // elements: depth below the surface root
    // Geometry.
    Poly poly;         // elements
    Vec3 normal;       // elements
    double area = 0;   // elements: polygon area; clusters: sum over oriented surfaces
    Vec3 center;       // area centroid
    double radius = 0; // bounding-sphere radius about center
    Aabb box;
    int surf_begin = 0, surf_end = 0;  // clusters: range in Hierarchy::surface_order
    // Material (elements; clusters keep the largest reflectance below them for the oracle).
    Rgb rho, emission;
    double rho_max = 0;
    // Radiometry, all in radiance units.
    Rgb L;           // radiance; clusters and inner elements: area average of their leaves
    Rgb G;           // gathered irradiance / pi of this iteration
    Rgb Lmin, Lmax;  // range of leaf radiance below (sender-side error term of the oracle)
    std::array<Rgb, kBins> S{};      // clusters: sum over surfaces of L * A * max(0, +-n_axis)
    std::array<double, kBins> W{};   // clusters: sum over surfaces of A * max(0, +-n_axis)
    // (Whether a leaf is enclosed, and its closure factors: Enclosure, enclosure.h.)
    bool dead = false;               // un-refined away (the slot is not reused)
    // Elements: the pocket the surface faces into (Pockets::compute): a set of surfaces,
    // across objects, whose escape rays meet only each other -- the inside of a closed crate and
    // the outside of what lies in it. Light passes only between surfaces of one pocket. Every
    // surface that sees open space shares pocket 0.
    int pocket = 0;
    // Clusters: index into Hierarchy::pocket_sets (the pockets of the surfaces below).
    int pocket_set = -1;
    uint64_t key = 0;                // stable identity (seeds link jitter independent of creation order)
    std::vector<int> in_links, out_links;

    bool is_cluster() const { return kind == NodeKind::Cluster; }
    bool is_leaf() const { return children.empty(); }
};

// One input polygon piece (a triangle or convex planar quad) after fan-splitting n-gons.
struct Primitive {
    int object = -1;
    int face = -1;                  // Blender polygon index within the object
    Poly poly;                      // current placement (internal frame)
    Poly poly0;                     // as given (internal frame); moves map poly0 -> poly
    std::array<int, 4> corner{};    // Blender corner index of each vertex
    int front = -1, back = -1;      // oriented surface ids (back = -1 when one-sided)
    int local = -1;                 // index among its object's primitives (part of its surfaces' keys)
};

// A surface root's geometry as the cluster samplers of link evaluation need it, kept in
// surface_order order so that a cluster's surfaces are one contiguous range. Walking the
// nodes themselves (about 1 kB apart) for every cluster link cost a furnished room's solve
// a quarter of its time in cache misses.
struct SurfaceGeom {
    Poly poly;
    Vec3 normal;
    double area = 0;
    double share = 1;  // Poly::first_share()
    int root = -1;
    int object = -1;
    int pocket = 0;  // Node::pocket
};

struct Surface {
    int root = -1;  // its element-quadtree root node
    int prim = -1;
    bool back = false;
};

class Hierarchy {
public:
    // Builds primitives, oriented surfaces and the cluster tree. Without clustering every
    // surface hangs directly below the root (the unclustered HR baseline).
    void build(const SceneDesc& scene, bool use_clustering);

    // Splits an element into 4 children (kept for later re-use); returns nothing new if split.
    void subdivide(int node);
    // Cluster bookkeeping after geometry changed (center, box, radius, bins), from its
    // surfaces; or from its children's, which must be current (the same up to rounding).
    void refresh_cluster_geometry(int node);
    void cluster_geometry_from_children(int node);
    // Per node, whether some (kEmitsAny) and every (kEmitsAll) surface below it emits (an
    // element, the surface roots and their quadtrees: itself), from the emission now. Set before a final gather,
    // which asks it per point; nodes made since are unknown to it.
    static constexpr uint8_t kEmitsAny = 1, kEmitsAll = 2;
    void index_emitters();
    // What emits() says of a node index_emitters has not seen: that it emits, that it does not,
    // or what the emission says now (an element's own, a cluster's surface roots').
    enum class Unknown { Emits, Dark, Look };
    // Whether a node emits or holds a surface that does (`all`: whether every surface below it
    // emits), as index_emitters found; of a node made since, as `unknown` says.
    bool emits(int node, Unknown unknown, bool all = false) const;
    // Places objects rigidly: p = R p0 + t in the internal frame (R row-major 3x3), their
    // surfaces and elements re-derived from the given geometry, clusters above refreshed.
    // `whole`: the clusters above them from their surfaces and the surface tables anew, bit
    // for bit as a build makes them. Otherwise (a live drag's placement, put back after) the
    // clusters above them from their children and the tables only where their surfaces are:
    // the same up to rounding, in time that follows the objects and the tree's depth, not the
    // scene. `own`: per object its primitives, when the caller knows them (else found among all).
    // `threads` (parallel_for's): the primitives are placed in parallel, each its own subtrees.
    void place_objects(const std::vector<std::pair<int, Rigid>>& placed, bool whole = true,
                       const std::vector<std::vector<int>>* own = nullptr, int threads = 1);
    void place_object(int object, const Rigid& placement, bool whole = true) {
        place_objects({{object, placement}}, whole);
    }
    // Nodes of an object (its cluster subtree, or its surfaces' quadtrees when unclustered).
    std::vector<int> object_nodes(int object) const;
    // The clusters among them, level by level: the object's own cluster, then each level below
    // it (none when the object is not a cluster).
    std::vector<std::vector<int>> object_cluster_levels(int object) const;
    // The clusters above an object's own node, from its parent up to the root (the root alone
    // for an object that has no node).
    std::vector<int> clusters_above(int object) const;

    // --- Objects added to or removed from a built hierarchy (dynamic environments).
    // Builds object `object` of `scene` (already appended there) into the tree where a fresh
    // build of the whole scene would put it: its primitives (in the existing internal frame),
    // surfaces, cluster subtree and any collection cluster it needs. Node keys do not depend
    // on build order, so the new nodes get the keys a fresh build gives them. surface_order,
    // the clusters' surface ranges and the geometry of the clusters above are rebuilt.
    // Returns the topmost node created (-1: no cluster was made, e.g. unclustered or no surface).
    int add_object(const SceneDesc& scene, int object, bool use_clustering);
    // Takes an object out: its nodes are retired and leave the tree, so do collection clusters
    // left empty (a fresh build makes no node for them), and its primitives belong to no object
    // any more (object -1).
    struct Removed {
        int deepest = -1;  // the deepest surviving cluster that held it (the root at worst)
        int elements = 0;  // element nodes retired (retire)
    };
    Removed remove_object(int object);
    // --- Retiring nodes (un-refinement, removed objects). A retired node is marked dead (its
    // slot is not reused, so ids stay stable) and its link lists are freed; its links are the
    // link store's to kill. Each returns how many element nodes it retired: what the solver's
    // element count (Stats::element_nodes) loses.
    // Node `id` alone; its place in the tree is the caller's to change.
    int retire(int id);
    // Every node below `id`, which becomes a leaf.
    int retire_below(int id);
    // Surfaces of removed objects keep their slot (ids stay stable) with a dead root.
    bool surface_dead(int s) const { return nodes[surfaces[s].root].dead; }
    // The side of primitive `prim` that a ray travelling along d arrives at: its front when d
    // runs against the front's normal, else its back; -1 when that side does not exist or was
    // removed.
    int side_met(int prim, const Vec3& d) const;
    // Bounding box of an object's current placement (`own`: its primitives, when the caller
    // knows them; else found among all).
    Aabb object_box(int object, const std::vector<int>* own = nullptr) const;
    static uint64_t mix(uint64_t a, uint64_t b);
    // The pockets of the surfaces below each cluster (set_pocket_sets), sorted.
    std::vector<std::vector<int>> pocket_sets;
    // Every cluster's pocket set from its surfaces' pockets; after those change.
    void set_pocket_sets();
    // Whether some surface below `node` (or the element itself) lies in pocket p.
    bool holds_pocket(int node, int p) const {
        const Node& n = nodes[size_t(node)];
        if (!n.is_cluster()) return n.pocket == p;
        if (n.pocket_set < 0) return false;
        const std::vector<int>& v = pocket_sets[size_t(n.pocket_set)];
        return std::binary_search(v.begin(), v.end(), p);
    }
    // Whether light can pass between a and b at all: some pocket has surfaces below both.
    bool share_pocket(int a, int b) const;
    // A link's sample element, or the nearest ancestor of it that an un-refinement left alive
    // (retire_below marks un-refined elements dead; their radiance is no longer kept).
    int live_element(int id) const {
        while (nodes[size_t(id)].dead && nodes[size_t(id)].parent >= 0 && !nodes[size_t(nodes[size_t(id)].parent)].is_cluster())
            id = nodes[size_t(id)].parent;
        return id;
    }
    // The leaf below element `id` that holds x (a point in its plane): down through the
    // child on x's side of the lines Poly::child splits along. A point on a line goes to one
    // child, always the same; one off the polygon to the child on its side of every line.
    // Always ends at a leaf, whatever x is (NaN, or far away).
    int leaf_at(int id, const Vec3& x) const;
    // Node ids of the clusters strictly above a surface root, root first.
    const std::vector<int>& ancestors_of_surface(int s) const { return surface_ancestors_[s]; }
    // Heap bytes of everything but the nodes (primitives, surfaces and their tables, the
    // samplers' tree, pockets' sets): what the build made, for the memory estimate.
    double tables_bytes() const;

    Chunked<Node, 12> nodes;  // in chunks that never move (chunked.h)
    std::vector<Primitive> prims;
    // A textured polygon's reflectance pieces (ObjectDesc::pieces) in the primitive that holds
    // them: position = v0 + a (v1 - v0) + b (v[n-1] - v0) of its polygon, so they move with it.
    struct PrimPiece {
        double a = 0, b = 0, area = 0;
        Rgb rho, emission;
        bool emits = false;  // its emission stands (ObjectDesc::pieces_emit)
    };
    std::vector<std::vector<PrimPiece>> prim_pieces;  // per primitive (empty: uniform)
    // An element's reflectance: the area mean of its primitive's pieces inside it (the
    // nearest piece when none is), or `uniform` for a primitive without pieces.
    Rgb element_rho(const Node& e, const Rgb& uniform) const;
    // ... and its emission, likewise from pieces that carry one.
    Rgb element_emission(const Node& e, const Rgb& uniform) const;
    // The reflectance at point x of element `id` (its primitive's nearest piece), or its rho.
    Rgb rho_at(int id, const Vec3& x) const;
    // (Re)binds object `o`'s pieces to its primitives `ids` (after make_prims or new pieces).
    void bind_pieces(const ObjectDesc& o, const std::vector<int>& ids);
    // After the scene's emission, reflectance or pieces changed: every element of a live
    // object takes its polygon's material again (element_rho, element_emission), and every
    // cluster its largest reflectance below (refresh_cluster_geometry). Radiance is left as
    // it is: the solver's to gather again.
    void apply_materials(const SceneDesc& scene);
    // Sums over the surface roots of live objects (both sides of a two-sided polygon count):
    // their area, and their area weighted by each one's largest emission and largest
    // reflectance channel. The scene's reference radiance is made from them.
    struct SurfaceTotals {
        double area = 0;
        double emission = 0;     // sum of area x emission.max()
        double reflectance = 0;  // sum of area x rho.max()
    };
    SurfaceTotals surface_totals() const;
    // The primitive of element e when it has pieces, else -1.
    int pieces_prim(const Node& e) const;
    std::vector<Surface> surfaces;
    std::vector<int> surface_order;   // surface ids; each cluster's are contiguous
    // Parallel to surface_order. Refreshed wherever surface roots move, change their pocket
    // or surface_order changes (refresh_surface_geom()).
    std::vector<SurfaceGeom> surface_geom;
    // Running sum of surface_geom areas (size + 1): a cluster's surfaces are drawn by area in
    // O(log n) from its contiguous range.
    std::vector<double> area_prefix;
    // Large clusters whose surfaces have few distinct normals and pockets (rooms,
    // furniture): their projected area toward any direction is a sum over those normals, so a
    // cluster link costs O(log n) instead of a scan of every surface below it.
    struct FacingGroup {
        Vec3 normal;
        int pocket = 0;
        double area = 0;
    };
    struct FacingSummary {
        bool valid = false;              // false: scan the surfaces
        std::vector<FacingGroup> groups; // distinct (normal, pocket), summed area
    };
    std::vector<FacingSummary> facing_summary;        // per node (empty vector: none)
    bool has_facing_summary(int node) const { return size_t(node) < facing_summary.size() && facing_summary[size_t(node)].valid; }
    static constexpr int kSummaryMinSurfaces = 256, kSummaryMaxNormals = 24;
    // The cluster tree as a large cluster's sampler descends it (TreeSampler, transfer.cpp):
    // per cluster, the facing data of the nodes below it that a draw picks among, in one
    // contiguous range, so that a draw reads a level in a few cache lines instead of each
    // child's Node (most of a kilobyte apart). The binary object trees are read up to
    // kSamplerFanOut nodes a level (grandchildren and below), so a draw takes a few levels
    // where the tree has many: each level's read is a cache miss, once per ray. Refreshed
    // with surface_geom.
    static constexpr size_t kSamplerFanOut = 16;
    struct SamplerRecord {
        int id = -1;
        bool cluster = false, dead = false;
        int pocket = -1, geom = -1;     // a surface root's pocket and index in surface_geom
        int first = 0, count = 0;       // a cluster's own records (sampler_first's range)
        double area = 0;
        std::array<double, kBins> W{};  // a cluster's Node::W; a surface root's normal in W[0..2]
    };
    std::vector<SamplerRecord> sampler_records;
    std::vector<int> sampler_first;  // per node (clusters): where its records' range starts
    // Remakes surface_geom, area_prefix, the facing summaries and the samplers' tree from the
    // nodes; call it after the clusters' geometry (refresh_cluster_geometry) is current.
    void refresh_surface_geom();
    // The area prefix where surface_geom changed (`ranges` of surface_order positions, each
    // [begin, end)) and past it, and the facing summaries and samplers' data of the clusters
    // `changed` alone (those whose surfaces or children's geometry changed); the tree's shape
    // as it was. The same as a whole refresh up to rounding.
    void refresh_surface_tables(std::vector<std::pair<int, int>> ranges, const std::vector<int>& changed);
    // Whether surface_geom (and the samplers' data made with it) matches the nodes (tests).
    bool surface_geom_current() const;
    std::vector<int> object_node;     // per object: its cluster node (-1 if it has no surface)
    std::vector<int> cluster_node;    // per ClusterDesc: its node (-1 if empty)
    std::vector<int> object_of_env;   // per object: 1 if directly in the scene (environment)
    // Per object: 0 when it casts no shadow (an area light, lights.h): it hides nothing behind
    // it, so its coupling comes on top of the rest of what a receiver sees.
    std::vector<char> object_occludes;
    // Whether a sender's coupling counts toward a receiver's closure (gather_plan.cpp): everything
    // but an object that hides nothing, and clusters above objects (most of what they hold does).
    bool closes(int node) const {
        const int o = nodes[size_t(node)].object;
        return o < 0 || size_t(o) >= object_occludes.size() || object_occludes[size_t(o)];
    }
    int root = -1;
    // All geometry is stored in a normalised frame: p_internal = (p_world - origin) / unit,
    // with unit the scene's bounding-box diagonal. Every tolerance, ray offset and area
    // limit is then the same at any scene scale, and so are the results.
    Vec3 origin;
    double unit = 1.0;
    // Snapped to a 2^-36 grid (1.5e-11 of the diagonal): the same scene at another scale
    // then maps to bit-identical internal geometry, so even tie-breaking decisions of the
    // oracle and the rays agree.
    Vec3 to_internal(const Vec3& p) const {
        auto snap = [](double v) { return std::ldexp(std::nearbyint(std::ldexp(v, 36)), -36); };
        Vec3 q = (p - origin) / unit;
        return {snap(q.x), snap(q.y), snap(q.z)};
    }
    Aabb scene_box;          // internal frame
    double scene_diag = 1.0; // internal frame (1 unless the scene is empty)
    size_t skipped_polygons = 0;  // zero-area input polygons (they get the colour of their neighbours)
    // Concave n-gons no corner sees whole and too large (or too tangled) to clip into ears:
    // fanned from their first corner, so some pieces face the wrong way (a warning says so).
    size_t unfanned_polygons = 0;

private:
    std::vector<uint8_t> emits_;  // index_emitters()
    int new_node(NodeKind kind, int parent);
    int build_object_tree(std::vector<int>& prim_ids, int begin, int end, int parent, int object, uint64_t key);
    void add_surfaces_of_prims(const std::vector<int>& prim_ids, int begin, int end, int parent);
    void finish_cluster(int node);
    // build() with clustering: the collection clusters and the object trees under the root.
    void build_collection_tree(const SceneDesc& scene, std::vector<std::vector<int>>& prims_of);
    // The object's polygons as primitives appended to `prims`; returns their ids.
    std::vector<int> make_prims(const ObjectDesc& o, int object);
    // Per object a key from its name (and how many earlier objects share it): an object keeps
    // its key when others are added or removed, so a fresh build casts the same rays.
    static uint64_t object_key(const SceneDesc& scene, int object);
    // The node of collection cluster c, made (with its parents) when missing.
    int ensure_cluster_node(const SceneDesc& scene, int c);
    // surface_order and every cluster's [surf_begin, surf_end) from a walk of the tree (the
    // caller refreshes the clusters' geometry, then surface_geom).
    void rebuild_surface_order();
    void set_surface_ancestors(int s);
    void set_surface_material(const SceneDesc& scene, int s);
    std::vector<std::vector<int>> surface_ancestors_;
    std::vector<uint64_t> object_keys_;
};

}  // namespace radiosity
