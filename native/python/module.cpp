// Thin pybind11 skin over the native solver: numpy in, numpy out, the GIL released while
// solving, and an asynchronous job the add-on polls. No logic lives here.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>

#include "radiosity/job.h"
#include "radiosity/solver.h"

namespace py = pybind11;
using namespace radiosity;

namespace {

template <class T>
using Arr = py::array_t<T, py::array::c_style | py::array::forcecast>;

void check_shape(const py::array& a, int cols, const char* what, size_t rows) {
    bool ok = cols == 0 ? (a.ndim() == 1 && size_t(a.shape(0)) == rows)
                        : (a.ndim() == 2 && size_t(a.shape(0)) == rows && a.shape(1) == cols);
    if (!ok) throw py::value_error(std::string(what) + ": wrong shape");
}

std::vector<Rgb> rgb_rows(const Arr<double>& a, const char* what, size_t rows) {
    check_shape(a, 3, what, rows);
    auto r = a.unchecked<2>();
    std::vector<Rgb> out(rows);
    for (size_t i = 0; i < rows; ++i) out[i] = {r(i, 0), r(i, 1), r(i, 2)};
    return out;
}

// None -> empty (the per-polygon values), else (rows, 3).
std::vector<Rgb> optional_rgb(const py::object& a, const char* what, size_t rows) {
    if (a.is_none()) return {};
    return rgb_rows(a.cast<Arr<double>>(), what, rows);
}

// None -> no pieces, else (face (P,) int32, position (P,3), area (P,), reflectance (P,3)
// [, emission (P,3)]); `emit` tells whether the emission was given.
std::vector<TexturePiece> texture_pieces(const py::object& a, const std::string& name, bool* emit = nullptr) {
    std::vector<TexturePiece> out;
    if (emit) *emit = false;
    if (a.is_none()) return out;
    auto t = a.cast<py::tuple>();
    if (t.size() != 4 && t.size() != 5)
        throw py::value_error("object '" + name + "': pieces must be (face, position, area, reflectance[, emission])");
    auto face = t[0].cast<Arr<int32_t>>();
    auto pos = t[1].cast<Arr<double>>();
    auto area = t[2].cast<Arr<double>>();
    const size_t n = size_t(face.size());
    check_shape(area, 0, "piece area", n);
    if (pos.ndim() != 2 || size_t(pos.shape(0)) != n || pos.shape(1) != 3)
        throw py::value_error("object '" + name + "': piece positions must be (P,3)");
    const std::vector<Rgb> rho = rgb_rows(t[3].cast<Arr<double>>(), "piece reflectance", n);
    const bool has_emission = t.size() == 5 && !t[4].is_none();
    const std::vector<Rgb> em = has_emission ? rgb_rows(t[4].cast<Arr<double>>(), "piece emission", n) : std::vector<Rgb>();
    if (emit) *emit = has_emission;
    auto p = pos.unchecked<2>();
    out.resize(n);
    for (size_t i = 0; i < n; ++i) {
        out[i].face = face.data()[i];
        out[i].position = {p(ssize_t(i), 0), p(ssize_t(i), 1), p(ssize_t(i), 2)};
        out[i].area = area.data()[i];
        out[i].rho = rho[i];
        if (has_emission) out[i].emission = em[i];
    }
    return out;
}

ObjectDesc make_object(const std::string& name, int cluster, const Arr<double>& verts,
                       const Arr<int32_t>& loop_starts, const Arr<int32_t>& loop_totals, const Arr<int32_t>& corner_verts,
                       const Arr<double>& reflectance, const Arr<double>& emission, const py::object& two_sided,
                       bool occluder, const py::object& corner_reflectance, const py::object& corner_emission,
                       const py::object& pieces, bool output, const py::object& written_corners) {
    ObjectDesc o;
    o.name = name;
    o.occluder = occluder;
    o.output = output;
    o.cluster = cluster;
    if (verts.ndim() != 2 || verts.shape(1) != 3) throw py::value_error("object '" + name + "': vertices must be (V,3)");
    auto v = verts.unchecked<2>();
    o.vertices.resize(size_t(v.shape(0)));
    for (ssize_t i = 0; i < v.shape(0); ++i) o.vertices[i] = {v(i, 0), v(i, 1), v(i, 2)};
    const size_t nf = size_t(loop_starts.size());
    check_shape(loop_starts, 0, "loop_starts", nf);
    check_shape(loop_totals, 0, "loop_totals", nf);
    o.loop_starts.assign(loop_starts.data(), loop_starts.data() + nf);
    o.loop_totals.assign(loop_totals.data(), loop_totals.data() + nf);
    o.corner_verts.assign(corner_verts.data(), corner_verts.data() + corner_verts.size());
    o.reflectance = rgb_rows(reflectance, "reflectance", nf);
    o.emission = rgb_rows(emission, "emission", nf);
    if (!two_sided.is_none()) {
        auto t = two_sided.cast<Arr<uint8_t>>();
        check_shape(t, 0, "two_sided", nf);
        o.two_sided.assign(t.data(), t.data() + nf);
    }
    o.corner_reflectance = optional_rgb(corner_reflectance, "corner_reflectance", o.corner_verts.size());
    o.corner_emission = optional_rgb(corner_emission, "corner_emission", o.corner_verts.size());
    o.pieces = texture_pieces(pieces, name, &o.pieces_emit);
    if (!written_corners.is_none()) {
        auto w = written_corners.cast<Arr<uint8_t>>();
        check_shape(w, 0, "written_corners", o.corner_verts.size());
        o.written_corners.assign(w.data(), w.data() + o.corner_verts.size());
    }
    return o;
}

int add_object(SceneDesc& s, const std::string& name, int cluster, const Arr<double>& verts,
               const Arr<int32_t>& loop_starts, const Arr<int32_t>& loop_totals, const Arr<int32_t>& corner_verts,
               const Arr<double>& reflectance, const Arr<double>& emission, const py::object& two_sided,
               bool occluder, const py::object& corner_reflectance, const py::object& corner_emission,
               const py::object& pieces, bool output, const py::object& written_corners) {
    return s.add_object(make_object(name, cluster, verts, loop_starts, loop_totals, corner_verts, reflectance,
                                    emission, two_sided, occluder, corner_reflectance, corner_emission, pieces,
                                    output, written_corners));
}

// A solver plus the job that may be running it.
struct PySolver {
    std::shared_ptr<Solver> solver;
    Job job;
    PySolver(const SceneDesc& scene, const Settings& st) : solver(std::make_shared<Solver>(scene, st)) {}
    void idle() const {
        if (const_cast<Job&>(job).running()) throw std::runtime_error("a solve is running");
    }
    void solved() const {
        idle();
        if (!solver->solved()) throw std::runtime_error("no finished solve");
    }
    // A solve or an update (`step`) on this thread, the GIL released while it runs.
    void run(void (Solver::*step)(Control*)) {
        idle();
        py::gil_scoped_release release;
        (solver.get()->*step)(nullptr);
    }
    // ... or in the background job that running(), progress(), cancel() and wait() follow.
    void start(void (Solver::*step)(Control*)) {
        auto s = solver;
        job.start([s, step](Control& c) { (s.get()->*step)(&c); });
    }
};

// (F,3) per polygon or (3,) for all.
std::vector<Rgb> rgb_list(const Arr<double>& a) {
    if (a.ndim() == 1 && a.shape(0) == 3) return {Rgb{a.data()[0], a.data()[1], a.data()[2]}};
    if (a.ndim() != 2 || a.shape(1) != 3) throw py::value_error("values must be (F,3) or (3,)");
    return rgb_rows(a, "values", size_t(a.shape(0)));
}

// Interleaved RGB values (r, g, b, r, ...) as an (n,3) array.
py::array_t<float> rgb_array(const std::vector<float>& v) {
    py::array_t<float> out({py::ssize_t(v.size() / 3), py::ssize_t(3)});
    std::copy(v.begin(), v.end(), out.mutable_data());
    return out;
}

py::dict stats_dict(const Stats& s) {
    py::dict d;
#define F(x) d[#x] = s.x
    F(input_surfaces); F(primitives); F(skipped_polygons); F(objects); F(clusters); F(elements);
    F(element_nodes); F(links); F(cluster_links); F(surface_links); F(history_links); F(obj_env_links);
    F(env_env_links); F(obj_obj_links); F(env_env_links_recomputed); F(rays); F(links_evaluated);
    F(refined_by_oracle); F(avoided_by_progressive); F(refined_by_closure); F(iterations); F(refine_rounds); F(residual);
    F(capped); F(memory_capped); F(memory_bytes); F(iteration_capped); F(no_emitters); F(seconds_build); F(seconds_link); F(seconds_solve);
    F(seconds_total); F(warnings); F(occluded_links); F(env_env_links_tested); F(env_env_links_rejected);
    F(obj_env_links_removed); F(links_created); F(history_reactivated); F(seconds_adjust);
    F(env_env_links_rays_clear); F(history_links_recomputed); F(history_links_stale); F(link_sweeps); F(seconds_sweeps); F(gather_plans); F(seconds_gather_plan); F(closed_pockets); F(pocket_surfaces); F(objects_added); F(objects_removed); F(links_removed);
    F(gather_points); F(gather_corners); F(gather_covered); F(gather_links); F(gather_rays); F(gather_bytes); F(gather_forecast_bytes); F(gather_kept); F(gather_replayed); F(gather_fresh_points); F(gather_near); F(gather_near_rays); F(gather_lamp_rays); F(gather_shared); F(gather_sealed);
    F(gather_probe_rays); F(gather_probes_kept); F(contact_surfaces); F(seconds_contacts);
    py::dict phases;
    for (const auto& p : s.phases) phases[py::str(p.first)] = p.second;
    d["phases"] = phases;
    py::dict phase_rays;
    for (const auto& p : s.phase_rays) phase_rays[py::str(p.first)] = p.second;
    d["phase_rays"] = phase_rays;
    d["mode"] = s.mode_incremental ? "incremental" : "full";
    // Why an update solved in full, as a stable code (None: it did not).
    d["update_fallback"] = s.update_fallback == UpdateFallback::none ? py::object(py::none())
                                                                    : py::object(py::str(fallback_code(s.update_fallback)));
#undef F
    return d;
}

// A preview's counts and an object's costs as dicts, each field under its own name.
py::dict preview_counts_dict(const FinalGather::PreviewCounts& k) {
    py::dict d;
#define F(x) d[#x] = k.x
    F(points); F(lamps); F(transfers); F(rays); F(uncovered); F(covered); F(deferred);
#undef F
    return d;
}

py::dict object_cost_dict(const Solver::ObjectCost& c) {
    py::dict d;
#define F(x) d[#x] = c.x
    F(point_rays); F(links); F(link_rays); F(history_links); F(history_link_rays);
#undef F
    return d;
}

// A 4x4 matrix (row-major), as Solver::move_object and Solver::preview take it.
std::array<double, 16> matrix16(const Arr<double>& m) {
    if (m.ndim() != 2 || m.shape(0) != 4 || m.shape(1) != 4) throw py::value_error("matrix must be 4x4");
    std::array<double, 16> a{};
    std::copy(m.data(), m.data() + 16, a.begin());
    return a;
}

// Solver.preview: with the objects of `moves` ({object_id: 4x4 matrix}, as move_object takes)
// placed there, direct light re-traced and the rest as solved, the corners that change
// ({object_id: (corner indices, (k,3) values)}; the others keep corner_radiance's value) and
// what it re-traced. Changes nothing of the solution. `work`: as Solver::preview's (-1:
// Settings.preview_work; 0: every point).
py::tuple preview(PySolver& s, const py::dict& moves, int64_t work) {
    s.solved();
    std::map<int, std::array<double, 16>> mv;
    for (const auto& item : moves) {
        const int id = item.first.cast<int>();
        const auto m = Arr<double>::ensure(item.second);
        if (!m) throw py::value_error("matrix must be 4x4");
        mv[id] = matrix16(m);
    }
    FinalGather::PreviewCounts k;
    std::vector<CornerPatch> patches;
    {
        py::gil_scoped_release release;
        patches = s.solver->preview(mv, &k, work);
    }
    py::dict out;
    for (const CornerPatch& p : patches)  // three values a corner
        out[py::int_(p.object)] = py::make_tuple(
            py::array_t<int32_t>(py::ssize_t(p.corners.size()), p.corners.data()), rgb_array(p.values));
    return py::make_tuple(out, preview_counts_dict(k));
}

// Solver.leaf_mesh: the solution's leaves of one object as a mesh with their values.
py::dict leaf_mesh(const PySolver& s, int object, bool lighting_only) {
    s.solved();
    LeafMesh lm = s.solver->leaf_mesh(object, lighting_only);
    py::array_t<double> verts({py::ssize_t(lm.vertices.size()), py::ssize_t(3)});
    double* v = verts.mutable_data();
    for (const Vec3& p : lm.vertices) *v++ = p.x, *v++ = p.y, *v++ = p.z;
    py::array_t<float> vals({py::ssize_t(lm.values.size()), py::ssize_t(3)});
    float* c = vals.mutable_data();
    for (const Rgb& x : lm.values) *c++ = float(x.r), *c++ = float(x.g), *c++ = float(x.b);
    py::dict d;
    d["vertices"] = verts;
    d["loop_totals"] = py::array_t<int32_t>(py::ssize_t(lm.loop_totals.size()), lm.loop_totals.data());
    d["corner_verts"] = py::array_t<int32_t>(py::ssize_t(lm.corner_verts.size()), lm.corner_verts.data());
    d["values"] = vals;
    d["source_face"] = py::array_t<int32_t>(py::ssize_t(lm.source_face.size()), lm.source_face.data());
    return d;
}

void bind_settings(py::module_& m) {
    py::class_<Settings>(m, "Settings")
        .def(py::init<>())
        .def_static("preset", &Settings::preset)
        .def_readwrite("error_threshold", &Settings::error_threshold)
        .def_readwrite("min_area_fraction", &Settings::min_area_fraction)
        .def_readwrite("below_floor_levels", &Settings::below_floor_levels)
        .def_readwrite("max_elements", &Settings::max_elements)
        .def_readwrite("max_links", &Settings::max_links)
        .def_readwrite("max_memory_mb", &Settings::max_memory_mb)
        .def_readwrite("use_clustering", &Settings::use_clustering)
        .def_readwrite("progressive_refinement", &Settings::progressive_refinement)
        .def_readwrite("rays_per_link", &Settings::rays_per_link)
        .def_readwrite("replay_rays", &Settings::replay_rays)
        .def_readwrite("max_iterations", &Settings::max_iterations)
        .def_readwrite("max_refine_rounds", &Settings::max_refine_rounds)
        .def_readwrite("tolerance", &Settings::tolerance)
        .def_readwrite("threads", &Settings::threads)
        .def_readwrite("crease_angle_deg", &Settings::crease_angle_deg)
        .def_readwrite("gather_rays", &Settings::gather_rays)
        .def_readwrite("gather_min_rays", &Settings::gather_min_rays)
        .def_readwrite("gather_share", &Settings::gather_share)
        .def_readwrite("preview_work", &Settings::preview_work)
        .def_readwrite("cycles_corner_points", &Settings::cycles_corner_points)
        .def_readwrite("gather_sealed_solids", &Settings::gather_sealed_solids)
        .def_readwrite("closure_rays", &Settings::closure_rays)
        .def_readwrite("closure_refine_tolerance", &Settings::closure_refine_tolerance)
        .def_readwrite("threshold_floor", &Settings::threshold_floor)
        .def_readwrite("closure_refine_passes", &Settings::closure_refine_passes)
        .def_readwrite("seed", &Settings::seed)
        .def("validate", &Settings::validate);
}

// Blender lights and world (native/include/radiosity/lights.h).
void bind_lights(py::module_& m) {
    py::enum_<LightDesc::Type>(m, "LightType")
        .value("POINT", LightDesc::Type::Point)
        .value("SPOT", LightDesc::Type::Spot)
        .value("SUN", LightDesc::Type::Sun)
        .value("SKY", LightDesc::Type::Sky);
    auto vec3 = [](Vec3 LightDesc::*f) {
        return std::make_pair([f](const LightDesc& l) { const Vec3& v = l.*f; return std::array<double, 3>{v.x, v.y, v.z}; },
                              [f](LightDesc& l, std::array<double, 3> v) { l.*f = {v[0], v[1], v[2]}; });
    };
    auto pos = vec3(&LightDesc::position), dir = vec3(&LightDesc::direction);
    py::class_<LightDesc>(m, "Light")
        .def(py::init<>())
        .def_readwrite("name", &LightDesc::name)
        .def_readwrite("type", &LightDesc::type)
        .def_property("position", pos.first, pos.second)
        .def_property("direction", dir.first, dir.second)
        .def_readwrite("radius", &LightDesc::radius)
        .def_readwrite("angle", &LightDesc::angle)
        .def_readwrite("spot_size", &LightDesc::spot_size)
        .def_readwrite("spot_blend", &LightDesc::spot_blend)
        .def_readwrite("spot_cos_falloff", &LightDesc::spot_cos_falloff)
        .def_property("intensity",
                      [](const LightDesc& l) { return std::array<double, 3>{l.intensity.r, l.intensity.g, l.intensity.b}; },
                      [](LightDesc& l, std::array<double, 3> v) { l.intensity = {v[0], v[1], v[2]}; })
        // The world's radiance per direction, (H, W, 3) equirectangular (environment.h).
        .def("set_environment", [](LightDesc& l, const Arr<double>& a) {
            if (a.ndim() != 3 || a.shape(2) != 3) throw py::value_error("environment map must be (H, W, 3)");
            const auto r = a.unchecked<3>();
            std::vector<Rgb> t(size_t(a.shape(0) * a.shape(1)));
            for (py::ssize_t i = 0; i < a.shape(0); ++i)
                for (py::ssize_t j = 0; j < a.shape(1); ++j) t[size_t(i * a.shape(1) + j)] = {r(i, j, 0), r(i, j, 1), r(i, j, 2)};
            l.env = std::make_shared<const EnvMap>(int(a.shape(1)), int(a.shape(0)), std::move(t));
        }, py::arg("radiance"))
        .def_property_readonly("has_environment", [](const LightDesc& l) { return bool(l.env); })
        .def("validate", &LightDesc::validate);
}

void bind_scene(py::module_& m) {
    py::class_<SceneDesc>(m, "Scene")
        .def(py::init<>())
        .def("add_cluster", &SceneDesc::add_cluster, py::arg("name"), py::arg("parent") = -1)
        .def("add_object", &add_object, py::arg("name"), py::arg("cluster"), py::arg("vertices"),
             py::arg("loop_starts"), py::arg("loop_totals"), py::arg("corner_verts"), py::arg("reflectance"),
             py::arg("emission"), py::arg("two_sided") = py::none(), py::arg("occluder") = true,
             py::arg("corner_reflectance") = py::none(), py::arg("corner_emission") = py::none(),
             py::arg("pieces") = py::none(), py::arg("output") = true, py::arg("written_corners") = py::none())
        .def("add_light", &SceneDesc::add_light, py::arg("light"))
        .def_property_readonly("light_count", [](const SceneDesc& s) { return s.lights().size(); })
        .def_property_readonly("object_count", [](const SceneDesc& s) { return s.objects().size(); })
        .def_property_readonly("polygon_count", &SceneDesc::polygon_count);
}

// Edits of the kept solution, applied by the next update().
void bind_solver_edits(py::class_<PySolver>& cls) {
    cls
        .def("move_object", [](PySolver& s, int object, const Arr<double>& m) {
            s.idle();
            s.solver->move_object(object, matrix16(m));
        }, py::arg("object_id"), py::arg("matrix"))
        // Objects added / removed since the solve; applied by the next update().
        .def("add_object", [](PySolver& s, const std::string& name, int cluster, const Arr<double>& verts,
                              const Arr<int32_t>& loop_starts, const Arr<int32_t>& loop_totals,
                              const Arr<int32_t>& corner_verts, const Arr<double>& reflectance,
                              const Arr<double>& emission, const py::object& two_sided, bool occluder,
                              const py::object& corner_reflectance, const py::object& corner_emission,
                              const py::object& pieces, bool output, const py::object& written_corners) {
            s.idle();
            return s.solver->add_object(make_object(name, cluster, verts, loop_starts, loop_totals, corner_verts,
                                                    reflectance, emission, two_sided, occluder, corner_reflectance,
                                                    corner_emission, pieces, output, written_corners));
        }, py::arg("name"), py::arg("cluster"), py::arg("vertices"), py::arg("loop_starts"), py::arg("loop_totals"),
           py::arg("corner_verts"), py::arg("reflectance"), py::arg("emission"), py::arg("two_sided") = py::none(),
           py::arg("occluder") = true, py::arg("corner_reflectance") = py::none(),
           py::arg("corner_emission") = py::none(), py::arg("pieces") = py::none(), py::arg("output") = true,
           py::arg("written_corners") = py::none())
        .def("remove_object", [](PySolver& s, int object) {
            s.idle();
            s.solver->remove_object(object);
        }, py::arg("object_id"))
        .def("add_cluster", [](PySolver& s, const std::string& name, int parent) {
            s.idle();
            return s.solver->add_cluster(name, parent);
        }, py::arg("name"), py::arg("parent") = -1)
        .def("set_emission", [](PySolver& s, int object, const Arr<double>& v) {
            s.idle();
            s.solver->set_emission(object, rgb_list(v));
        }, py::arg("object_id"), py::arg("emission"))
        .def("set_reflectance", [](PySolver& s, int object, const Arr<double>& v) {
            s.idle();
            s.solver->set_reflectance(object, rgb_list(v));
        }, py::arg("object_id"), py::arg("reflectance"))
        // A texture changed: its values at the corners (the output's) and, for the transport,
        // its pieces inside the polygons (None: none, each polygon uniform).
        .def("set_corner_materials", [](PySolver& s, int object, const py::object& rho, const py::object& e,
                                        const py::object& pieces) {
            s.idle();
            const ObjectDesc& o = s.solver->scene().objects().at(size_t(object));
            const size_t nc = o.corner_count();
            s.solver->set_corner_materials(object, optional_rgb(rho, "corner_reflectance", nc),
                                           optional_rgb(e, "corner_emission", nc));
            bool emit = false;
            std::vector<TexturePiece> p = texture_pieces(pieces, o.name, &emit);
            s.solver->set_texture_pieces(object, std::move(p), emit);
        }, py::arg("object_id"), py::arg("reflectance") = py::none(), py::arg("emission") = py::none(),
           py::arg("pieces") = py::none())
        .def("set_light", [](PySolver& s, int index, const LightDesc& l) {
            s.idle();
            s.solver->set_light(index, l);
        }, py::arg("index"), py::arg("light"));
}

// Solves and updates, in the caller's thread or as a background job.
void bind_solver_runs(py::class_<PySolver>& cls) {
    cls
        .def("update", [](PySolver& s) { s.run(&Solver::update); })
        .def("start_update", [](PySolver& s) { s.start(&Solver::update); })
        .def("running", [](PySolver& s) { return s.job.running(); })
        .def("progress", [](PySolver& s) { return s.job.progress(); })
        .def("cancel", [](PySolver& s) { s.job.cancel(); })
        .def("wait", [](PySolver& s, double timeout) {
            py::gil_scoped_release release;
            return s.job.wait(timeout);
        }, py::arg("timeout") = -1.0);
}

// What a solution gives: corner values, the live drag's, the leaves, stats and costs.
void bind_solver_output(py::class_<PySolver>& cls) {
    cls
        .def("corner_radiance", [](const PySolver& s, int object) {
            s.solved();
            return rgb_array(s.solver->corner_radiance(object));
        }, py::arg("object_id"))
        // Live drag: with the objects of `moves` ({object_id: 4x4 matrix}, as move_object
        // takes) placed there, direct light re-traced and the rest as solved, the corners that
        // change ({object_id: (corner indices, (k,3) values)}; the others keep corner_radiance's
        // value) and what it re-traced. Changes nothing of the solution. `work`: as
        // Solver::preview's (-1: Settings.preview_work; 0: every point).
        .def("preview", &preview, py::arg("moves"), py::arg("work") = -1)
        .def("corner_irradiance", [](const PySolver& s, int object) {
            s.solved();
            return rgb_array(s.solver->corner_irradiance(object));
        }, py::arg("object_id"))
        .def("leaf_mesh", &leaf_mesh, py::arg("object_id"), py::arg("lighting_only") = false)
        .def("radiance_at", [](const PySolver& s, int object, int face, std::array<double, 3> p) {
            s.solved();
            Rgb c = s.solver->radiance_at(object, face, {p[0], p[1], p[2]});
            return std::array<double, 3>{c.r, c.g, c.b};
        })
        .def("stats", [](const PySolver& s) {
            s.idle();
            return stats_dict(s.solver->stats());
        })
        .def("object_costs", [](const PySolver& s) {
            s.solved();
            py::list out;
            for (const Solver::ObjectCost& c : s.solver->object_costs()) out.append(object_cost_dict(c));
            return out;
        });
}

}  // namespace

PYBIND11_MODULE(radiosity_native, m) {
    m.doc() = "Clustering-based hierarchical radiosity solver (native core of the Blender add-on)";
    py::register_exception<Cancelled>(m, "Cancelled");
    // Every code stats()["update_fallback"] may hold (the add-on words each one).
    py::list fallbacks;
    for (UpdateFallback f : kUpdateFallbacks) fallbacks.append(fallback_code(f));
    m.attr("update_fallbacks") = py::tuple(fallbacks);
    bind_settings(m);
    bind_lights(m);
    bind_scene(m);
    py::class_<PySolver> solver(m, "Solver");
    solver.def(py::init<const SceneDesc&, const Settings&>(), py::arg("scene"), py::arg("settings"))
        .def("solve", [](PySolver& s) { s.run(&Solver::solve); })
        .def("start", [](PySolver& s) { s.start(&Solver::solve); });
    bind_solver_edits(solver);
    bind_solver_runs(solver);
    bind_solver_output(solver);
}
