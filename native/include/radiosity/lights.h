// Blender lights that are not surfaces (point, spot, sun) and a uniform world (sky): their
// direct light is computed at the leaf elements with shadow rays and enters the radiosity
// system as reflected radiance rho * E / pi, so it bounces through the links from there.
// Area lights are not here: the add-on hands them in as emitting one-sided polygons.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "radiosity/environment.h"
#include "radiosity/rigid.h"
#include "radiosity/vec.h"

namespace radiosity {

inline bool same_texels(const EnvMap& a, const EnvMap& b) {
    for (size_t i = 0; i < a.texels().size(); ++i)
        if (a.texels()[i].r != b.texels()[i].r || a.texels()[i].g != b.texels()[i].g || a.texels()[i].b != b.texels()[i].b)
            return false;
    return true;
}

// Units are Cycles' after the add-on's conversion (measured, see addon/radiosity/core/lights.py):
//   Point, Spot: `intensity` = radiant intensity (W/sr per colour): unoccluded irradiance
//                I cos(theta) / d^2 (Blender: power W x colour / 4 pi).
//   Sun:         `intensity` = irradiance on a surface facing the sun (Blender: strength W/m^2).
//   Sky:         `intensity` = radiance of the uniform world (Blender: Background colour x strength),
//                or, with `env`, a factor on the map's radiance in each direction (environment.h).
struct LightDesc {
    enum class Type : int { Point = 0, Spot = 1, Sun = 2, Sky = 3 };
    std::string name;
    Type type = Type::Point;
    Vec3 position;              // Point, Spot (world space)
    Vec3 direction{0, 0, -1};   // Spot: cone axis; Sun: the direction the light travels (unit)
    double radius = 0;          // Point, Spot: radius of the emitting disk (soft shadows)
    double angle = 0;           // Sun: angular diameter of the sun disk (radians)
    double spot_size = kPi;     // Spot: full cone angle (radians, (0, pi])
    double spot_blend = 0;      // Spot: smooth fraction of the cone edge, [0, 1]
    // Spot: intensity also falls with the cosine to the axis (Cycles before Blender 4.0).
    bool spot_cos_falloff = false;
    Rgb intensity;
    // Sky: the world's radiance per direction (shared, immutable: copies of the light are cheap).
    std::shared_ptr<const EnvMap> env;

    // Throws InputError naming the light.
    void validate() const;
    // Whether `o` lights the scene exactly as this one does (the name aside).
    bool same_light(const LightDesc& o) const {
        return type == o.type && position.x == o.position.x && position.y == o.position.y &&
               position.z == o.position.z && direction.x == o.direction.x && direction.y == o.direction.y &&
               direction.z == o.direction.z && radius == o.radius && angle == o.angle && spot_size == o.spot_size &&
               spot_blend == o.spot_blend && spot_cos_falloff == o.spot_cos_falloff && intensity.r == o.intensity.r &&
               intensity.g == o.intensity.g && intensity.b == o.intensity.b &&
               (env == o.env || (env && o.env && env->width() == o.env->width() &&
                                 env->height() == o.env->height() && same_texels(*env, *o.env)));
    }
};

// The outcomes of a point's or an element's shadow rays in the order cast (bit k of the
// words: ray k blocked).
struct LampRays {
    int count = 0;
    std::vector<uint64_t> blocked;
};

// Shadow rays an element's direct term casts per child and light (DirectLight, direct_light.h).
int element_shadow_rays(int rays_per_link, LightDesc::Type type);

class Hierarchy;
class SceneDesc;
class Visibility;

// Direct light at one point (the output's final gather, final_gather.cpp): irradiance / pi at
// x (internal frame) with unit normal n from every point, spot and sun light and the sky of
// `scene`, m stratified samples per light (4m for the sky, one for a point or spot light
// without a radius), shadow rays through `vis`. A covered point (lying on another object's
// face: a floor under a box) gets nothing, as in Cycles.
struct PointLight {
    Rgb E;
    bool partial = false;  // a shadow edge of some light crosses the samples
    int rays = 0;
};
PointLight direct_light_at(const SceneDesc& scene, const Hierarchy& h, const Visibility& vis, const Vec3& x,
                           const Vec3& n, bool covered, int m, uint64_t seed);
// direct_light_at for an uncovered point, its shadow rays recorded in `out`. With `old` (the
// same point's record: same seed and lights) and `changed` (the boxes where geometry moved
// since), a ray that meets none of the boxes takes its recorded outcome: equal to tracing the
// point afresh, at the cost of the rays a move can change. PointLight::rays counts rays cast.
PointLight direct_light_replay(const SceneDesc& scene, const Hierarchy& h, const Visibility& vis, const Vec3& x,
                               const Vec3& n, int m, uint64_t seed, const LampRays* old,
                               const std::vector<Aabb>* changed, LampRays& out);

}  // namespace radiosity
