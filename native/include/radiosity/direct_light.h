// DirectLight: the direct light of Blender's point, spot and sun lights and the world at the
// leaf elements (lights.h), kept per node with the shadow rays that made it, and the element
// splits that light needs. It changes no hierarchy node itself: the splits it wants are made by
// its caller (refine's `split`), and the children it no longer needs are handed back (coarsen).
#pragma once
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "radiosity/hierarchy.h"
#include "radiosity/lights.h"
#include "radiosity/rigid.h"
#include "radiosity/scene.h"
#include "radiosity/settings.h"
#include "radiosity/visibility.h"

namespace radiosity {

class DirectLight {
public:
    // What shadow rays are cast into and how: the scene (its lights; which objects occlude),
    // Embree's scene and the settings (seed, rays per link, threads). Held for one call only.
    struct Sight {
        const SceneDesc& scene;
        const Visibility& vis;
        const Settings& settings;
    };

    // --- The cached terms, irradiance / pi (Node::G's unit: a leaf's outgoing radiance gains
    // rho x direct). A node's area mean over the element, and the spread (max - min) of its
    // four children's estimates; 0 unless computed for the current lights and placements.
    Rgb direct(int node) const;
    double spread(int node) const;
    // Per element node: emission + rho x the lamps' direct light, the area mean over its leaves
    // (largest channel): the radiance a full solve's first linking judges links by. The cached
    // terms are used as they are: before an update lights the leaves again, the old lights'.
    std::vector<float> first_bounce(const Hierarchy& h) const;
    // Flux the lights bring into the scene over `total_area` of surfaces, in radiance x
    // internal area (the reference radiance's units).
    static double power(const SceneDesc& scene, const Hierarchy& h, double total_area);
    // The memory its recorded shadow rays take (for the memory estimate).
    double bytes(const SceneDesc& scene, int rays_per_link) const;

    // --- What makes the terms stale.
    void clear();            // a full solve builds the hierarchy anew
    void relight();          // a light changed, objects were added or removed: every term again
    void forget_contacts();  // surfaces added or removed: find_contacts finds every one's again
    // Objects moved (`boxes`: their old and new boxes): find_contacts looks again at the
    // surfaces near them alone, and keeps the rest. Until it does, no contact is known.
    void moved_contacts(const std::vector<Aabb>& boxes);
    // The objects are placed at `poses` now. When the terms were made at other placements,
    // each goes stale: with `replay` (a move that replays rays: the moved objects' old and new
    // boxes), a node away from the boxes keeps its shadow rays, those meeting no box to keep
    // their outcome; otherwise it is lit afresh. Also fits the per-node arrays to `h`.
    void invalidate(const Hierarchy& h, const std::vector<Rigid>& poses, const std::vector<Aabb>* replay);
    // Whether the lights or placements changed since the light splits were last checked
    // (refine and the update then coarsen first); asking resets it.
    bool take_recheck();

    // --- Lighting and splitting. Every call lights the nodes it needs with shadow rays.
    // invalidate, then the term of every leaf in `leaves` lacking one (nothing without lights).
    void prepare(const Hierarchy& h, const Sight& sight, const std::vector<int>& leaves, const std::vector<Rigid>& poses,
                 const std::vector<Aabb>* replay);
    // Lit leaves among `leaves` whose light varies across them by more than `threshold` (times
    // their reflectance) ask `split(id)` to split them (the caller decides whether the element
    // may split, splits it in `h` and says whether it did); their children are lit at once
    // and split again if needed, so a shadow edge reaches the resolution limit in one call.
    // True if any split.
    bool refine(const Hierarchy& h, const Sight& sight, double threshold, const std::vector<int>& leaves,
                const std::function<bool(int)>& split);
    // After the lights or placements changed: the nodes whose children neither the light nor
    // a link below needs (`referenced`: per node, an end of a live link), top-down as refine
    // would decide now; their light splits below are forgotten, and the caller drops their
    // children (before they are lit again: those cost no rays).
    std::vector<int> coarsen(const Hierarchy& h, const Sight& sight, double threshold, const std::vector<char>& referenced);
    // Pruning: a reference in `refs` (per node) for each child the light still needs.
    void keep(const Hierarchy& h, const Sight& sight, double threshold, std::vector<int>& refs);

    // --- Contacts: surfaces of other objects lying on a surface, facing it (a box standing on
    // a floor), where Cycles finds the points unlit.
    // Finds them, unless found for the surfaces as they are.
    void find_contacts(const Hierarchy& h, const SceneDesc& scene, int threads);
    // The surface touching `surface` at p, or -1.
    int contact(const Hierarchy& h, int surface, const Vec3& p) const;
    // Whether corner k of a primitive, just inside its face, lies in a contact.
    bool corner_in_contact(const Hierarchy& h, const Primitive& p, int k) const;
    // Per surface: the surfaces touching it, as last found.
    const std::vector<std::vector<int>>& contacts() const { return contacts_; }
    // What find_contacts did since last asked (surfaces looked at, seconds); asking resets it.
    struct ContactWork {
        int64_t surfaces = 0;
        double seconds = 0;
    };
    ContactWork take_contact_work() { return std::exchange(contact_work_, ContactWork{}); }

private:
    // Per node: direct and spread computed for the current lights and placements (kLit); made
    // before a move, its shadow rays to replay (kStale); or not at all.
    enum : uint8_t { kNone = 0, kLit = 1, kStale = 2 };
    // Lights `ids` (their four children's estimates), replaying stale nodes' rays.
    void compute(const Hierarchy& h, const Sight& sight, const std::vector<int>& ids);
    // Top-down over the element trees: nodes whose children the light needs (`lit`), and
    // nodes whose children neither the light nor a link below needs (`drop`).
    void walk(const Hierarchy& h, const Sight& sight, double threshold, const std::vector<char>& link_below,
              std::vector<int>& lit, std::vector<int>& drop);
    void resize(size_t nodes);  // the per-node arrays to the node count
    // Sets the contacts found aside (kept_contacts_) until find_contacts asks for them: none
    // is known meanwhile, as when they were forgotten.
    void stash_contacts();

    std::vector<Rgb> direct_;       // per node: area mean of the direct term over the element
    std::vector<float> spread_;     // per node: max - min over its four children's estimates
    std::vector<uint8_t> have_;     // per node: kNone, kLit or kStale
    std::vector<LampRays> rays_;    // per node: the shadow rays its direct term was computed with
    std::vector<Aabb> clips_;       // where geometry moved since stale nodes were lit
    std::vector<uint8_t> split_;    // per node: subdivided because its direct light varies
    std::vector<Rigid> poses_;      // object placements the terms were made with
    std::vector<std::vector<int>> contacts_;  // per surface: touching surfaces of other objects
    std::vector<std::vector<int>> kept_contacts_;  // contacts_ set aside after moves, ...
    std::vector<Aabb> contact_boxes_;              // ... and the boxes where they may have changed
    ContactWork contact_work_;
    bool recheck_ = false;          // lights or placements changed: try merging light splits
};

}  // namespace radiosity
