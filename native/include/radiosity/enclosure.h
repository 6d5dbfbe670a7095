// Enclosure: per leaf element, whether it is enclosed -- none of its escape rays finds open
// space, so its form factors must sum to 1 -- and the closure factors that correct its
// couplings toward that sum (gathering.cpp set_closure). A side table of the hierarchy,
// indexed by node id, kept apart from the nodes because only the closure correction and the
// output read it.
//
// It decides the answers itself, with each node's escape rays (decide), when a closure pass
// meets a leaf not yet answered and when an update's AdjustSystem has its deciders ask again
// after a move. Gathering owns it and sets the factors. The gather plan copies the factors for
// its sweeps; the final gather reads both for the output points of enclosed leaves.
//
// An element split after its parent was answered takes the parent's answer, decider and
// factors until it is a leaf in a closure pass itself: fit() gives them to every node made
// since it last ran. So that what they take is what the parent held when it split, every
// writer fits first (nothing writes a node's entry between a split and the next fit).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "radiosity/gather_plan.h"
#include "radiosity/hierarchy.h"

namespace radiosity {

struct Settings;
class Visibility;

class Enclosure {
public:
    // --- Growth.
    // The table to the hierarchy's nodes: each node made since the last fit takes its parent
    // element's answer, decider and factors (a surface root or a cluster: none known).
    void fit(const Hierarchy& h);
    void clear();  // a full solve builds the hierarchy anew
    size_t size() const { return enclosed_.size(); }
    // Heap bytes held at `nodes` nodes (the memory estimate's forecast).
    double bytes(size_t nodes) const;

    // --- The answers, per node (a node beyond the last fit: unknown, no decider).
    // 1: no escape ray found open space; 0: one did; -1: not known yet.
    int8_t enclosed(int node) const { return at(enclosed_, node, int8_t(-1)); }
    // The node whose escape rays gave the answer (itself, or the ancestor it inherited it
    // from; -1: none), and the index of its ray that found open space (-1: none did). After a
    // move only the rays that pass through a moved object's old or new box are cast again.
    int decider(int node) const { return at(decider_, node, -1); }
    int escape_ray(int node) const { return at(escape_ray_, node, int8_t(-1)); }

    // --- Deciding. A node's escape rays leave from random points of its polygon, lifted off
    // it, in cosine-distributed directions, and reach beyond the scene; the same per node key.
    // What they are cast into: the hierarchy (the node's polygon, the scene's size), Embree's
    // scene and the settings (seed, rays per node). Held for one call only.
    struct Sight {
        const Hierarchy& h;
        const Visibility& vis;
        const Settings& settings;
    };
    // Decides (or, after a move, decides again) whether node `id`'s escape rays find open
    // space, and makes it its own decider. With `moved_boxes`, it was decided before and did
    // not move: only rays through a moved object's old or new box can have changed outcome.
    // Called from several threads at once, each for its own node (fitted already).
    void decide(const Sight& s, int id, const std::vector<Aabb>* moved_boxes);
    // The answer forgotten (the decider moved: all its rays are cast again).
    void forget(int node) { enclosed_[size_t(node)] = -1; }
    // The deciders of the live elements' known answers, ascending.
    std::vector<int> deciders(const Hierarchy& h) const;
    // Every live element with a decider takes its decider's answer (after deciders asked again).
    void follow_deciders(const Hierarchy& h);

    // --- The closure factors, per node (leaves; a node beyond the last fit: no correction).
    const ClosureFactors& factors(int node) const {
        static const ClosureFactors none;
        return size_t(node) < factors_.size() ? factors_[size_t(node)] : none;
    }
    void set_factors(int node, const ClosureFactors& f) { factors_[size_t(node)] = f; }

private:
    // The node decided with its own escape rays: `open_ray` the first that found open space,
    // -1 when none did (enclosed).
    void record(int node, int open_ray) {
        decider_[size_t(node)] = node;
        enclosed_[size_t(node)] = open_ray < 0 ? 1 : 0;
        escape_ray_[size_t(node)] = int8_t(open_ray);
    }
    // An enclosed decider's ray `ray` finds open space after a move.
    void reopen(int node, int ray) {
        enclosed_[size_t(node)] = 0;
        escape_ray_[size_t(node)] = int8_t(ray);
    }
    template <class T, class U>
    static T at(const std::vector<U>& v, int node, T none) {
        return size_t(node) < v.size() ? T(v[size_t(node)]) : none;
    }

    std::vector<ClosureFactors> factors_;  // per node: c_own, c_inherited, fill
    std::vector<int8_t> enclosed_;         // per node: 1, 0 or -1 (enclosed())
    std::vector<int8_t> escape_ray_;       // per node: escape_ray()
    std::vector<int32_t> decider_;         // per node: decider()
};

}  // namespace radiosity
