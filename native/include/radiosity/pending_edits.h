// PendingEdits: what the solver's setters record between updates (moves, additions, removals,
// material changes) until an update or a full solve takes it, and what stays per object from
// one update to the next (its placement, whether it was removed).
#pragma once
#include <algorithm>
#include <map>
#include <utility>
#include <vector>

#include "radiosity/rigid.h"

namespace radiosity {

class PendingEdits {
public:
    // --- Recorded by the setters.
    // `object` is to be placed at `pose` (internal frame), in place of a move recorded before.
    void record_move(int object, const Rigid& pose) { moves_[object] = pose; }
    // An object added to a solved scene, for the next update to build into the solution.
    void record_add(int object) { adds_.push_back(object); }
    // Marks `object` removed and drops its pending move. True when the removal waits for the
    // next update: the object is `built` into the solution and is not an addition still
    // pending (which is forgotten). Otherwise the caller empties its scene slot at once.
    bool record_remove(int object, bool built) {
        if (size_t(object) >= removed_.size()) removed_.resize(size_t(object) + 1, 0);
        removed_[size_t(object)] = 1;
        moves_.erase(object);
        const auto it = std::find(adds_.begin(), adds_.end(), object);
        if (it != adds_.end()) {
            adds_.erase(it);
            return false;
        }
        if (built) removes_.push_back(object);
        return built;
    }
    // Emission, reflectance, a texture or a light changed.
    void record_materials() { materials_ = true; }

    // --- What is pending.
    bool any() const { return !moves_.empty() || materials_ || topology(); }
    bool topology() const { return !adds_.empty() || !removes_.empty(); }  // additions or removals
    bool materials() const { return materials_; }
    const std::map<int, Rigid>& moves() const { return moves_; }

    // --- Taken by the update or full solve that applies them (adds and removes in the order
    // recorded); they are no longer pending.
    std::map<int, Rigid> take_moves() { return std::exchange(moves_, {}); }
    std::vector<int> take_adds() { return std::exchange(adds_, {}); }
    std::vector<int> take_removes() { return std::exchange(removes_, {}); }
    bool take_materials() { return std::exchange(materials_, false); }

    // --- Kept per object from one update to the next.
    bool removed(int object) const { return object >= 0 && size_t(object) < removed_.size() && removed_[size_t(object)]; }
    // Each object's placement (internal frame), for as many objects as fit_poses last said:
    // an object added since has none until an update or a full solve builds it.
    const std::vector<Rigid>& poses() const { return poses_; }
    void fit_poses(size_t objects) { poses_.resize(objects); }
    void place(int object, const Rigid& pose) { poses_[size_t(object)] = pose; }
    // A removed object's slot: back at its geometry as given.
    void unplace(int object) {
        if (size_t(object) < poses_.size()) poses_[size_t(object)] = Rigid{};
    }

private:
    std::map<int, Rigid> moves_;
    std::vector<int> adds_, removes_;
    bool materials_ = false;
    std::vector<char> removed_;  // per object (grown as objects are removed): its slot stays, empty
    std::vector<Rigid> poses_;
};

}  // namespace radiosity
