// Scenes built from code: ground-truth cases for the tests, the benchmarks and the
// native demo (a room with a ceiling light and two boxes, the Cornell box, a furnace).
#pragma once
#include <array>
#include <string>

#include "radiosity/scene.h"

namespace radiosity::scenes {

// A planar quad a,b,c,d (counter-clockwise about its front normal) as an nu x nv grid object.
int add_grid(SceneDesc& s, const std::string& name, int cluster, const std::array<Vec3, 4>& q, int nu, int nv,
             Rgb rho, Rgb emission, bool two_sided = true);
// Axis-aligned box from lo to hi, faces outward (inward=false) or inward, n x n per face.
int add_box(SceneDesc& s, const std::string& name, int cluster, Vec3 lo, Vec3 hi, int n, Rgb rho, Rgb emission,
            bool inward = false, bool two_sided = true);

// An empty closed room (3 x 3 x 2.5, inward faces, 8 x 8 per face, reflectance 0.7) with a
// two-sided 0.6 m square lamp (radiance 10, black) hanging `gap` under its ceiling.
SceneDesc lamp_under_ceiling(double gap);
// Closed cube room (inward faces) of edge `size`, uniform rho and emission: B = E / (1 - rho).
SceneDesc furnace_cube(double rho, double emission, int n = 4, double size = 1.0);
// A closed non-convex room (an L-shaped room built from two boxes sharing an opening is
// hard to close exactly; instead a cube room with a box standing inside it).
SceneDesc furnace_room_with_box(double rho, double emission, int n = 4);
// Cornell box (NOTES.md data, metres).
SceneDesc cornell_box(int n = 8);
// The paper's box room: 300 x 300 x 250 room, ceiling light of radiance 12, two boxes.
SceneDesc box_room(int n = 8);
// The scene of the Blender light tests (tests/blender/scripts/light_scenes.py): a 4 x 4 m floor
// of 10 x 10 quads (rho 0.5), a 1 x 1 x 0.8 m box of 4 x 4 quads per side in a collection
// standing on it, and a 200 W point light of radius 0.1 m, colour (1, 0.8, 0.6), at `light`.
SceneDesc point_light_box_on_floor(Vec3 light);

}  // namespace radiosity::scenes
