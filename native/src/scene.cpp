#include "radiosity/scene.h"
#include "radiosity/held_bytes.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace radiosity {

int SceneDesc::add_cluster(const std::string& name, int parent) {
    if (parent < -1 || parent >= int(clusters_.size()))
        throw InputError("cluster '" + name + "': unknown parent cluster " + std::to_string(parent));
    clusters_.push_back({name, parent});
    return int(clusters_.size()) - 1;
}

namespace {
[[noreturn]] void fail(const ObjectDesc& o, const std::string& what) {
    throw InputError("object '" + o.name + "': " + what);
}
std::string poly_str(size_t f) { return "polygon " + std::to_string(f); }
}  // namespace

double ObjectDesc::bytes() const {
    return held_bytes(vertices) + held_bytes(loop_starts) + held_bytes(loop_totals) + held_bytes(corner_verts) +
           held_bytes(reflectance) + held_bytes(emission) + held_bytes(corner_reflectance) + held_bytes(corner_emission) +
           held_bytes(pieces) + held_bytes(two_sided) + held_bytes(written_corners);
}

std::vector<int> ObjectDesc::corner_polygons() const {
    std::vector<int> out(corner_count(), -1);
    for (size_t f = 0; f < polygon_count(); ++f)
        for (int k = 0; k < loop_totals[f]; ++k) out[size_t(loop_starts[f]) + size_t(k)] = int(f);
    return out;
}

void check_polygon_materials(const ObjectDesc& o, const std::vector<Rgb>& values, bool emission) {
    if (values.size() != o.polygon_count() && values.size() != 1) fail(o, "need one RGB per polygon or one for all");
    for (size_t f = 0; f < values.size(); ++f) {
        const Rgb& v = values[f];
        if (!finite(v)) fail(o, poly_str(f) + " has a non-finite value");
        for (int k = 0; k < 3; ++k) {
            if (v[k] < 0) fail(o, poly_str(f) + " has a negative value");
            if (emission && v[k] > kMaxEmission)
                fail(o, poly_str(f) + " has emission above 1e30 (the output would overflow)");
            if (!emission && v[k] >= 1) fail(o, poly_str(f) + " has reflectance >= 1");
        }
    }
}

void check_corner_materials(const ObjectDesc& o, const std::vector<Rgb>& rho, const std::vector<Rgb>& emission) {
    const size_t nc = o.corner_count();
    if (!rho.empty() && rho.size() != nc) fail(o, "corner reflectance needs one RGB per corner (or none)");
    if (!emission.empty() && emission.size() != nc) fail(o, "corner emission needs one RGB per corner (or none)");
    for (size_t c = 0; c < rho.size(); ++c)
        for (int k = 0; k < 3; ++k)
            if (!(rho[c][k] >= 0 && rho[c][k] < 1))
                fail(o, "corner " + std::to_string(c) + " has reflectance outside [0,1) or not finite");
    for (size_t c = 0; c < emission.size(); ++c)
        for (int k = 0; k < 3; ++k)
            if (!(emission[c][k] >= 0 && emission[c][k] <= kMaxEmission))
                fail(o, "corner " + std::to_string(c) + " has a negative, non-finite or too large emission");
}

void check_pieces(const ObjectDesc& o, std::vector<TexturePiece>& pieces) {
    for (size_t i = 0; i < pieces.size(); ++i) {
        const TexturePiece& q = pieces[i];
        const std::string what = "object '" + o.name + "': reflectance piece " + std::to_string(i);
        if (q.face < 0 || size_t(q.face) >= o.polygon_count()) throw InputError(what + " names a missing polygon");
        if (!finite(q.position)) throw InputError(what + " has a non-finite position");
        if (!std::isfinite(q.area) || q.area < 0) throw InputError(what + " has an area that is not a finite number >= 0");
        if (!finite(q.rho)) throw InputError(what + " has a non-finite reflectance");
        for (int k = 0; k < 3; ++k)
            if (q.rho[k] < 0 || q.rho[k] >= 1)
                throw InputError(what + " has reflectance outside [0,1) (energy would not converge)");
        if (!finite(q.emission)) throw InputError(what + " has a non-finite emission");
        for (int k = 0; k < 3; ++k)
            if (q.emission[k] < 0 || q.emission[k] > kMaxEmission)
                throw InputError(what + " has emission outside [0, 1e30]");
    }
    std::stable_sort(pieces.begin(), pieces.end(),
                     [](const TexturePiece& a, const TexturePiece& b) { return a.face < b.face; });
}

int SceneDesc::add_object(ObjectDesc o) {
    if (o.cluster < -1 || o.cluster >= int(clusters_.size()))
        fail(o, "unknown cluster " + std::to_string(o.cluster));
    const size_t nf = o.loop_starts.size();
    if (o.loop_totals.size() != nf) fail(o, "loop_starts and loop_totals differ in length");
    if (o.reflectance.size() != nf) fail(o, "reflectance needs one RGB per polygon");
    if (o.emission.size() != nf) fail(o, "emission needs one RGB per polygon");
    if (o.two_sided.empty()) o.two_sided.assign(nf, 1);
    if (o.two_sided.size() != nf) fail(o, "two_sided needs one flag per polygon");
    for (size_t i = 0; i < o.vertices.size(); ++i)
        if (!finite(o.vertices[i]))
            fail(o, "vertex " + std::to_string(i) + " has a non-finite coordinate (NaN or inf)");
    const int64_t nc = int64_t(o.corner_verts.size());
    for (int64_t c = 0; c < nc; ++c)
        if (o.corner_verts[c] < 0 || size_t(o.corner_verts[c]) >= o.vertices.size())
            fail(o, "corner " + std::to_string(c) + " refers to a missing vertex");
    for (size_t f = 0; f < nf; ++f) {
        if (o.loop_totals[f] < 3) fail(o, poly_str(f) + " has fewer than 3 corners");
        if (o.loop_starts[f] < 0 || int64_t(o.loop_starts[f]) + o.loop_totals[f] > nc)
            fail(o, poly_str(f) + " has corners outside the corner array");
        const Rgb& rho = o.reflectance[f];
        const Rgb& e = o.emission[f];
        if (!finite(rho)) fail(o, poly_str(f) + " has a non-finite reflectance");
        for (int k = 0; k < 3; ++k)
            if (rho[k] < 0 || rho[k] >= 1)
                fail(o, poly_str(f) + " has reflectance " + std::to_string(rho[k]) +
                            " outside [0,1) (energy would not converge)");
        if (!finite(e)) fail(o, poly_str(f) + " has a non-finite emission");
        for (int k = 0; k < 3; ++k) {
            if (e[k] < 0) fail(o, poly_str(f) + " has negative emission");
            if (e[k] > kMaxEmission) fail(o, poly_str(f) + " has emission above 1e30 (the output would overflow)");
        }
    }
    check_corner_materials(o, o.corner_reflectance, o.corner_emission);
    if (!o.written_corners.empty() && o.written_corners.size() != o.corner_verts.size())
        fail(o, "written_corners needs one flag per corner");
    check_pieces(o, o.pieces);
    objects_.push_back(std::move(o));
    return int(objects_.size()) - 1;
}

void ObjectDesc::fill_unwritten(std::vector<float>& v, const std::vector<float>& others) const {
    for (size_t c = 0; c < written_corners.size() && 3 * c + 2 < v.size() && 3 * c + 2 < others.size(); ++c)
        if (!written_corners[c])
            for (size_t k = 0; k < 3; ++k) v[3 * c + k] = others[3 * c + k];
}

size_t SceneDesc::polygon_count() const {
    size_t n = 0;
    for (const auto& o : objects_) n += o.polygon_count();
    return n;
}

}  // namespace radiosity
