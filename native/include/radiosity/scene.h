// The solver's input: objects (rigid polygon sets, world space) grouped into clusters
// (Blender collections). Validation happens here so the rest can trust its input.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "radiosity/lights.h"
#include "radiosity/vec.h"

namespace radiosity {

// Thrown for bad input; the message names the object and polygon.
struct InputError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

// Largest accepted emission: the output is float32 (max 3.4e38) and reflection can amplify
// emission up to 1 / (1 - 0.999) = 1000 times; larger values would come out as inf.
constexpr double kMaxEmission = 1e30;

struct ClusterDesc {
    std::string name;
    int parent = -1;  // -1: the root
};

// A texture's sample inside a polygon (addon/radiosity/textures.py: a piece of a cut copy of
// the mesh): what the material evaluates to around `position` (world space, as the vertices),
// over `area`. Elements take the area mean of the pieces inside them, points (the output's
// near field) the nearest piece's reflectance: a checker's squares inside one quad.
struct TexturePiece {
    int32_t face = -1;
    Vec3 position;
    double area = 0;
    Rgb rho;
    Rgb emission;  // read only when ObjectDesc::pieces_emit
};

struct ObjectDesc {
    std::string name;
    int cluster = -1;  // -1: its polygons are surfaces by themselves (paper 3.1.1)
    std::vector<Vec3> vertices;                 // world space
    std::vector<int32_t> loop_starts, loop_totals, corner_verts;  // Blender's polygon layout
    std::vector<Rgb> reflectance, emission;     // per polygon
    // Optional, per corner (empty: each corner takes its polygon's value): what a textured
    // material evaluates to at the corner, for the output only (radiance = emission +
    // reflectance x irradiance there, as Cycles shades a corner); the light transport uses
    // the per-polygon values, the texture's area mean over each polygon.
    std::vector<Rgb> corner_reflectance, corner_emission;
    // Optional (empty: each polygon uniform, its `reflectance`), sorted by face by
    // SceneDesc::add_object; a polygon without pieces keeps its value.
    std::vector<TexturePiece> pieces;
    bool pieces_emit = false;  // the pieces carry the texture's emission too (its polygons emit)
    std::vector<uint8_t> two_sided;             // per polygon
    // false: casts no shadow (rays pass through it), like a Blender area light in Cycles.
    bool occluder = true;
    // false: no colour of it is read (an instance, an area light, a mesh that cannot be
    // written): the final gather traces no point at its corners, which read the leaves. It
    // takes part in the light transport all the same.
    bool output = true;
    // Optional, per corner (empty: every corner when `output`): whether its colour is read. A
    // modifier's evaluated mesh (Array, Bevel, Subdivision Surface) has many corners for each
    // corner of the mesh written; the final gather traces points at the read ones only, and
    // the others read the leaves, as an object without output does.
    std::vector<uint8_t> written_corners;
    bool written(size_t corner) const { return output && (written_corners.empty() || written_corners[corner] != 0); }
    // Per-corner RGB values `v` (3 floats a corner) take `others`' at the corners not written.
    void fill_unwritten(std::vector<float>& v, const std::vector<float>& others) const;
    size_t polygon_count() const { return loop_starts.size(); }
    size_t corner_count() const { return corner_verts.size(); }
    bool textured() const { return !corner_reflectance.empty() || !corner_emission.empty(); }
    // Per corner, its polygon.
    std::vector<int> corner_polygons() const;
    // Heap bytes of its arrays (the solver's memory estimate).
    double bytes() const;
    // What corner c of polygon f leaves when `irradiance` (/ pi) arrives there: its own
    // reflectance and emission where the object is textured, else its polygon's.
    Rgb corner_shading(size_t f, size_t c, const Rgb& irradiance) const {
        const Rgb rho = corner_reflectance.empty() ? reflectance[f] : corner_reflectance[c];
        const Rgb e = corner_emission.empty() ? emission[f] : corner_emission[c];
        return e + rho * irradiance;
    }
};

// Throws InputError unless `values` holds one RGB per polygon of `o` or one for all, each
// finite and >= 0, and as an `emission` at most 1e30, as a reflectance below 1.
void check_polygon_materials(const ObjectDesc& o, const std::vector<Rgb>& values, bool emission);
// Throws InputError unless each array is empty or holds one valid value per corner of `o`.
void check_corner_materials(const ObjectDesc& o, const std::vector<Rgb>& reflectance, const std::vector<Rgb>& emission);
// Throws InputError unless every piece names a polygon of `o` and has a finite position, a
// finite area >= 0, a reflectance in [0, 1) and an emission in [0, 1e30]; sorts them by face.
void check_pieces(const ObjectDesc& o, std::vector<TexturePiece>& pieces);

class SceneDesc {
public:
    int add_cluster(const std::string& name, int parent = -1);
    // Validates and takes the object; throws InputError.
    int add_object(ObjectDesc obj);

    const std::vector<ClusterDesc>& clusters() const { return clusters_; }
    const std::vector<ObjectDesc>& objects() const { return objects_; }
    std::vector<ObjectDesc>& objects_mut() { return objects_; }
    size_t polygon_count() const;
    // Blender point/spot/sun lights and the world (lights.h); validates, throws InputError.
    int add_light(LightDesc light);
    const std::vector<LightDesc>& lights() const { return lights_; }
    std::vector<LightDesc>& lights_mut() { return lights_; }

private:
    std::vector<LightDesc> lights_;
    std::vector<ClusterDesc> clusters_;
    std::vector<ObjectDesc> objects_;
};

}  // namespace radiosity
