// exao._exao: the Python module's native part, one more thin shell over the one engine
// (engine/engine.h), like cli/ and api/. It turns numpy arrays into the engine's scene and
// receivers, options given as Python keywords into engine::Options (by the exao program's own
// parser, cli/common_options.h, so that a method name or option the engine learns works here
// unchanged), and runs every job on a thread of its own with the GIL released while the calling
// thread reports progress. python/exao/__init__.py is the public face; see its docstrings.

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "cli/common_options.h"
#include "cli/program.h"
#include "io/load_scene.h"
#include "core/scene.h"
#include "engine/engine.h"
#include "engine/geometry.h"
#include "engine/options.h"
#include "engine/receiver_check.h"

namespace py = pybind11;

namespace exao::python {
namespace {

// --- Jobs: the engine on its own thread, progress and cancelling on the caller's -------------

/// Thrown from the engine's progress callback (a worker thread) once the caller has cancelled:
/// TBB cancels the rest of the parallel work and rethrows it on the job's thread.
struct Cancelled {};

/// What the last job did, for tests (exao._last_job()): whether its engine work stopped early.
struct JobRecord {
  std::size_t done = 0;
  std::size_t total = 0;
  bool cancelled = false;  // the engine stopped before the end (a Cancelled unwound it)
};
std::mutex g_record_mutex;
JobRecord g_last_job;

struct Job {
  std::atomic<std::size_t> done{0};
  std::atomic<std::size_t> total{0};
  std::atomic<bool> cancel{false};

  /// The engine's progress callback: records (done, total) and unwinds once cancelled.
  ProgressCallback callback() {
    return [this](std::size_t d, std::size_t t) {
      std::size_t seen = done.load();
      while (d > seen && !done.compare_exchange_weak(seen, d)) {
      }
      total.store(t);
      if (cancel.load()) throw Cancelled{};
    };
  }
};

// How often the calling thread wakes to call `progress` and check for Ctrl-C: often enough for a
// status bar, rarely enough to cost nothing.
constexpr auto kPollInterval = std::chrono::milliseconds(100);

/// Runs work() on a new thread with the GIL released. Meanwhile the calling thread (holding the
/// GIL only while it does) calls progress(done, total) every kPollInterval and checks signals;
/// an exception from progress (or KeyboardInterrupt) sets job.cancel, waits for the engine to
/// unwind, and is re-raised as it was raised. `initial_total` > 0: progress(0, total) is called
/// once before the work starts, and progress(total, total) once after it ends.
void run_job(Job& job, const std::function<void()>& work, const py::object& progress, std::size_t initial_total) {
  const bool has_progress = !progress.is_none();
  job.total = initial_total;
  if (has_progress && initial_total > 0) progress(std::size_t{0}, initial_total);

  std::mutex mutex;
  std::condition_variable finished_cv;
  bool finished = false;
  bool cancelled = false;
  std::exception_ptr failure;
  std::thread worker([&] {
    try {
      work();
    } catch (const Cancelled&) {
      cancelled = true;
    } catch (...) {
      failure = std::current_exception();
    }
    {
      std::lock_guard lock(mutex);
      finished = true;
    }
    finished_cv.notify_all();
  });

  std::optional<py::error_already_set> raised;
  for (;;) {
    bool done_now = false;
    {
      py::gil_scoped_release release;
      std::unique_lock lock(mutex);
      done_now = finished_cv.wait_for(lock, kPollInterval, [&] { return finished; });
    }
    if (done_now) break;
    if (raised) continue;  // cancelling: wait for the engine to unwind
    try {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (has_progress) progress(job.done.load(), job.total.load());
    } catch (py::error_already_set& e) {
      raised = std::move(e);
      job.cancel = true;
    }
  }
  worker.join();
  {
    std::lock_guard lock(g_record_mutex);
    g_last_job = JobRecord{job.done.load(), job.total.load(), cancelled};
  }
  if (raised) throw std::move(*raised);
  if (failure) std::rethrow_exception(failure);
  if (has_progress && job.total.load() > 0) progress(job.total.load(), job.total.load());
}

// --- Options ----------------------------------------------------------------------------------

/// The library's option names (engine/options.h) as the Python keywords name them.
std::string keyword_message(const std::string& message) {
  static const std::pair<const char*, const char*> kNames[] = {
      {"origin_offset", "offset"}, {"pattern_seed", "seed"}, {"sidedness", "sided"},
      {"bvh.branching", "branching"}, {"bvh.max_leaf_size", "leaf_size"}, {"embree.rays", "embree_rays"},
  };
  const std::optional<std::string_view> option = engine::option_of(message);
  if (!option) return message;
  for (const auto& [internal, keyword] : kNames) {
    if (*option == internal) return keyword + message.substr(option->size());
  }
  return message;
}

[[noreturn]] void throw_value_error(const std::string& message) { throw py::value_error(keyword_message(message)); }

/// The keywords of Scene.ao / Scene.masks, as the exao program's flags would carry them.
struct AoOptions {
  int samples = 128;
  std::string radius;           // "5%", "0.5"; empty: the engine's default
  std::optional<float> radius_value;  // a number given as a number
  std::string falloff = "constant";
  std::optional<std::string> method;  // nullopt: the engine's default method
  std::optional<std::uint64_t> seed;
  std::optional<float> offset;
  std::string sided = "auto";
  std::optional<std::string> masks;
  int threads = 0;
  std::string isa = "auto";

  /// The cache key: every field, as text.
  [[nodiscard]] std::string key() const {
    std::string k = std::to_string(samples) + "|" + radius + "|" +
                    (radius_value ? std::to_string(std::bit_cast<std::uint32_t>(*radius_value)) : "-") + "|" + falloff +
                    "|" + method.value_or("-") + "|" + (seed ? std::to_string(*seed) : "-") + "|" +
                    (offset ? std::to_string(std::bit_cast<std::uint32_t>(*offset)) : "-") + "|" + sided + "|" +
                    masks.value_or("-") + "|" + std::to_string(threads) + "|" + isa;
    return k;
  }
};

[[nodiscard]] engine::Options to_engine(const AoOptions& o) {
  cli::SceneOptions scene;
  scene.sided = o.sided;
  cli::RayOptions rays;
  rays.samples = o.samples;
  rays.radius = o.radius;
  rays.falloff = o.falloff;
  rays.offset = o.offset;
  rays.threads = o.threads;
  cli::MethodOptions method;
  if (o.method) method.method = *o.method;
  if (o.masks) method.masks = *o.masks;
  method.isa = o.isa;
  Result<engine::Options> out = cli::make_options(scene, rays, method);
  if (!out) throw_value_error(out.error().message);
  if (o.radius_value) out->radius = engine::Length{*o.radius_value, false};
  if (o.seed) out->pattern_seed = *o.seed;
  if (auto ok = engine::check_serves(*out, engine::Receivers::Points); !ok) throw_value_error(ok.error().message);
  return *out;
}

AoOptions read_options(int samples, const py::object& radius, const std::string& falloff, const py::object& method,
                       const py::object& seed, const py::object& offset, const std::string& sided, const py::object& masks,
                       int threads, const std::string& isa) {
  AoOptions o;
  o.samples = samples;
  if (py::isinstance<py::str>(radius)) {
    o.radius = radius.cast<std::string>();
  } else if (py::isinstance<py::float_>(radius) || py::isinstance<py::int_>(radius)) {
    o.radius_value = radius.cast<float>();
  } else if (!radius.is_none()) {
    throw py::type_error("radius: must be a number (scene units) or a string such as '5%', got " +
                         std::string(py::str(py::type::of(radius).attr("__name__"))));
  }
  o.falloff = falloff;
  if (!method.is_none()) o.method = method.cast<std::string>();
  if (!seed.is_none()) {
    const auto s = seed.cast<long long>();
    if (s < 0) throw py::value_error("seed: must be a non-negative integer, got " + std::to_string(s));
    o.seed = static_cast<std::uint64_t>(s);
  }
  if (!offset.is_none()) o.offset = offset.cast<float>();
  o.sided = sided;
  if (!masks.is_none()) o.masks = masks.cast<std::string>();
  o.threads = threads;
  o.isa = isa;
  return o;
}

// --- numpy arrays -----------------------------------------------------------------------------

[[nodiscard]] std::string dtype_name(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

[[nodiscard]] std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

/// `object` as a float array of shape (n, 3) (n == expected_rows unless that is -1), read as
/// float32: float32 as it is (any strides: no copy), float64 rounded to float32; anything else
/// is a TypeError naming the argument.
py::array_t<float> float_rows(const py::object& object, const char* name, py::ssize_t expected_rows = -1) {
  if (!py::isinstance<py::array>(object)) {
    throw py::type_error(std::string(name) + ": expected a numpy float32 array of shape (n, 3), got " +
                         std::string(py::str(py::type::of(object).attr("__name__"))));
  }
  const auto array = py::reinterpret_borrow<py::array>(object);
  const char kind = array.dtype().kind();
  if (kind != 'f' || (array.itemsize() != 4 && array.itemsize() != 8)) {
    throw py::type_error(std::string(name) + ": expected float32 (or float64) values, got " + dtype_name(array));
  }
  if (array.ndim() != 2 || array.shape(1) != 3) {
    throw py::value_error(std::string(name) + ": expected shape (n, 3), got " + shape_text(array));
  }
  if (expected_rows >= 0 && array.shape(0) != expected_rows) {
    throw py::value_error(std::string(name) + ": expected " + std::to_string(expected_rows) + " rows (one per point), got " +
                          std::to_string(array.shape(0)));
  }
  if (array.itemsize() == 4) return py::reinterpret_borrow<py::array_t<float>>(array);
  return py::array_t<float>(array);  // float64: one float32 copy, as the engine reads floats
}

/// Row i of an (n, 3) float32 array of any strides.
[[nodiscard]] glm::vec3 row(const py::detail::unchecked_reference<float, 2>& a, py::ssize_t i) {
  return {a(i, 0), a(i, 1), a(i, 2)};
}

// --- Scene ------------------------------------------------------------------------------------

/// Triangles (the engine's Scene) and the engines built over them, kept for the next query with
/// the same options: building the BVH and the sample pattern is most of a small query's time.
class PyScene {
 public:
  explicit PyScene(Scene scene) : scene_(std::make_shared<const Scene>(std::move(scene))) {}

  [[nodiscard]] const Scene& scene() const { return *scene_; }

  /// The engine for these options, built on first use (with the GIL released: a BVH build
  /// takes seconds on large scenes).
  std::shared_ptr<const engine::Engine> engine_for(const AoOptions& o) {
    const engine::Options options = to_engine(o);
    const std::string key = o.key();
    {
      std::lock_guard lock(mutex_);
      for (const auto& [k, e] : engines_) {
        if (k == key) return e;
      }
    }
    std::optional<Result<engine::Engine>> built;
    {
      py::gil_scoped_release release;
      built = engine::Engine::build(*scene_, options, engine::Receivers::Points);
    }
    if (!*built) throw_value_error(built->error().message);
    auto engine = std::make_shared<const engine::Engine>(std::move(**built));
    std::lock_guard lock(mutex_);
    engines_.emplace_front(key, engine);
    if (engines_.size() > kCachedEngines) engines_.pop_back();
    return engine;
  }

 private:
  // A script alternates between a few settings (a preview and a final sample count, say).
  static constexpr std::size_t kCachedEngines = 4;
  std::shared_ptr<const Scene> scene_;
  std::mutex mutex_;
  std::list<std::pair<std::string, std::shared_ptr<const engine::Engine>>> engines_;
};

std::unique_ptr<PyScene> from_arrays(const py::object& vertices_object, const py::object& faces_object, const py::object& two_sided) {
  const py::array_t<float> vertices = float_rows(vertices_object, "vertices");
  if (!py::isinstance<py::array>(faces_object)) {
    throw py::type_error("faces: expected a numpy uint32 array of shape (m, 3), got " +
                         std::string(py::str(py::type::of(faces_object).attr("__name__"))));
  }
  const auto faces_array = py::reinterpret_borrow<py::array>(faces_object);
  const char kind = faces_array.dtype().kind();
  if (kind != 'u' && kind != 'i') throw py::type_error("faces: expected uint32 (or another integer type) indices, got " + dtype_name(faces_array));
  if (faces_array.ndim() != 2 || faces_array.shape(1) != 3) {
    throw py::value_error("faces: expected shape (m, 3), got " + shape_text(faces_array));
  }
  if (faces_array.shape(0) == 0) throw py::value_error("faces: empty, a scene needs at least one triangle");
  // Indices of any integer type are read as int64 (a copy only when they are not int64 already),
  // so a negative one is caught rather than wrapped around.
  const auto faces = py::array_t<std::int64_t>(faces_array);
  const auto f = faces.unchecked<2>();
  const auto v = vertices.unchecked<2>();
  const py::ssize_t n = v.shape(0);
  const py::ssize_t m = f.shape(0);

  std::vector<std::uint8_t> per_face;
  bool all_two_sided = true;
  if (py::isinstance<py::bool_>(two_sided)) {
    all_two_sided = two_sided.cast<bool>();
  } else if (py::isinstance<py::array>(two_sided)) {
    const auto flags = py::array_t<std::uint8_t>(py::reinterpret_borrow<py::array>(two_sided));
    if (flags.ndim() != 1 || flags.shape(0) != m) {
      throw py::value_error("two_sided: expected a bool or one flag per face (" + std::to_string(m) + ",), got shape " +
                            shape_text(flags));
    }
    const auto a = flags.unchecked<1>();
    per_face.resize(static_cast<std::size_t>(m));
    for (py::ssize_t t = 0; t < m; ++t) per_face[static_cast<std::size_t>(t)] = a(t) != 0;
  } else {
    throw py::type_error("two_sided: expected a bool or a numpy array of one flag per face");
  }

  // The triangles as the C++ API's Engine::build makes them (api/engine.cpp, add_mesh), so the
  // two give the same bits: zero-area triangles dropped (they block nothing), every vertex used
  // must be finite.
  Scene scene;
  scene.name = "arrays";
  scene.vertices.reserve(static_cast<std::size_t>(3 * m));
  scene.two_sided.reserve(static_cast<std::size_t>(m));
  scene.material.reserve(static_cast<std::size_t>(m));
  for (py::ssize_t t = 0; t < m; ++t) {
    glm::vec3 corner[3];
    for (py::ssize_t j = 0; j < 3; ++j) {
      const std::int64_t index = f(t, j);
      if (index < 0 || index >= n) {
        throw py::value_error("faces[" + std::to_string(t) + "]: vertex index " + std::to_string(index) +
                              " is out of range (there are " + std::to_string(n) + " vertices)");
      }
      corner[j] = row(v, static_cast<py::ssize_t>(index));
      if (!(std::isfinite(corner[j].x) && std::isfinite(corner[j].y) && std::isfinite(corner[j].z))) {
        throw py::value_error("vertices[" + std::to_string(index) + "]: not finite (NaN or infinite), used by face " +
                              std::to_string(t));
      }
    }
    const bool two = per_face.empty() ? all_two_sided : per_face[static_cast<std::size_t>(t)] != 0;
    scene.add_triangle(corner[0], corner[1], corner[2], two, -1);
  }
  if (scene.triangle_count() == 0) throw py::value_error("faces: every triangle has zero area");
  return std::make_unique<PyScene>(std::move(scene));
}

std::unique_ptr<PyScene> open_scene(const std::string& path) {
  Result<Scene> scene;
  {
    py::gil_scoped_release release;
    scene = exao::open_scene(path);
  }
  if (!scene) {
    // A name that is neither a built-in scene nor an existing file is FileNotFoundError; a file
    // that cannot be read, OSError; both with the loader's one line.
    const std::vector<std::string> builtins = builtin_scene_names();
    const bool builtin = std::ranges::find(builtins, path) != builtins.end();
    std::error_code ec;
    if (!builtin && !std::filesystem::exists(path, ec)) {
      PyErr_SetString(PyExc_FileNotFoundError, scene.error().message.c_str());
    } else {
      PyErr_SetString(PyExc_OSError, scene.error().message.c_str());
    }
    throw py::error_already_set();
  }
  return std::make_unique<PyScene>(std::move(*scene));
}

/// The receivers of a query: points and normals (n, 3), keys (n,) or None for 0..n-1.
std::vector<Receiver> read_receivers(const py::object& points_object, const py::object& normals_object, const py::object& keys_object) {
  const py::array_t<float> points = float_rows(points_object, "points");
  const py::array_t<float> normals = float_rows(normals_object, "normals", points.shape(0));
  const auto p = points.unchecked<2>();
  const auto nrm = normals.unchecked<2>();
  const py::ssize_t n = p.shape(0);
  std::vector<Receiver> receivers(static_cast<std::size_t>(n));
  std::optional<py::array_t<std::uint64_t>> keys;
  if (!keys_object.is_none()) {
    if (!py::isinstance<py::array>(keys_object)) throw py::type_error("keys: expected a numpy integer array of shape (n,)");
    const auto k = py::reinterpret_borrow<py::array>(keys_object);
    if (k.dtype().kind() != 'u' && k.dtype().kind() != 'i') throw py::type_error("keys: expected integers, got " + dtype_name(k));
    if (k.ndim() != 1 || k.shape(0) != n) {
      throw py::value_error("keys: expected shape (" + std::to_string(n) + ",), got " + shape_text(k));
    }
    keys = py::array_t<std::uint64_t>(k);
  }
  for (py::ssize_t i = 0; i < n; ++i) {
    Receiver& r = receivers[static_cast<std::size_t>(i)];
    r.position = row(p, i);
    r.normal = row(nrm, i);
    r.key = keys ? keys->at(i) : static_cast<std::uint64_t>(i);
    if (const char* problem = engine::receiver_problem(r.position, r.normal)) {
      throw py::value_error("receiver " + std::to_string(i) + " (points[" + std::to_string(i) + "], normals[" +
                            std::to_string(i) + "]): " + problem);
    }
  }
  return receivers;
}

/// Scene.ao and Scene.masks: one engine run into `outputs` (sized by the caller).
void run_query(const engine::Engine& engine, const std::vector<Receiver>& receivers, const engine::Outputs& outputs,
               const py::object& progress) {
  Job job;
  std::string error;
  run_job(
      job,
      [&] {
        engine::RunOptions run;
        run.progress = job.callback();
        if (auto ok = engine.run(receivers, outputs, run); !ok) error = ok.error().message;
      },
      progress, receivers.size());
  if (!error.empty()) throw_value_error(error);
}

// --- The exao program in-process (exao.bake, exao.render) -------------------------------------

/// Runs `exao <args>`; returns (status, error line or "").
std::pair<int, std::string> run_program(const std::vector<std::string>& args, const py::object& progress) {
  Job job;
  std::string error;
  int status = 1;
  cli::Embedding embedding;
  embedding.error = [&](const std::string& message) {
    if (error.empty()) error = message;
  };
  embedding.progress = job.callback();
  run_job(job, [&] { status = cli::run_program(args, &embedding); }, progress, 0);
  return {status, error};
}

}  // namespace
}  // namespace exao::python

PYBIND11_MODULE(_exao, m) {
  using namespace exao::python;
  m.doc() = "exao's native part; use the exao package (python/exao/__init__.py).";

  py::class_<PyScene>(m, "Scene")
      .def_static("from_arrays", &from_arrays, py::arg("vertices"), py::arg("faces"), py::arg("two_sided") = true)
      .def_static("open", &open_scene, py::arg("path"))
      .def_property_readonly("name", [](const PyScene& s) { return s.scene().name; })
      .def_property_readonly("triangle_count", [](const PyScene& s) { return s.scene().triangle_count(); })
      .def_property_readonly("notes", [](const PyScene& s) { return s.scene().report.notes; })
      .def_property_readonly("bounds",
                             [](const PyScene& s) {
                               const exao::Bounds b = s.scene().bounds();
                               return py::make_tuple(py::make_tuple(b.lo.x, b.lo.y, b.lo.z), py::make_tuple(b.hi.x, b.hi.y, b.hi.z));
                             })
      .def(
          "_run",
          [](PyScene& self, const py::object& points, const py::object& normals, const py::object& keys, bool masks,
             int samples, const py::object& radius, const std::string& falloff, const py::object& method,
             const py::object& seed, const py::object& offset, const std::string& sided, const py::object& mask_mode,
             int threads, const std::string& isa, const py::object& progress) -> py::object {
            const AoOptions options = read_options(samples, radius, falloff, method, seed, offset, sided, mask_mode, threads, isa);
            const std::vector<exao::Receiver> receivers = read_receivers(points, normals, keys);
            const std::shared_ptr<const exao::engine::Engine> engine = self.engine_for(options);
            const auto n = static_cast<py::ssize_t>(receivers.size());
            exao::engine::Outputs outputs;
            if (masks) {
              const auto words = static_cast<py::ssize_t>(engine->mask_words());
              py::array_t<std::uint64_t> out({n, words});
              outputs.masks = std::span<std::uint64_t>(out.mutable_data(), static_cast<std::size_t>(n * words));
              if (n > 0) run_query(*engine, receivers, outputs, progress);
              return out;
            }
            py::array_t<float> out(n);
            outputs.ao = std::span<float>(out.mutable_data(), static_cast<std::size_t>(n));
            if (n > 0) run_query(*engine, receivers, outputs, progress);
            return out;
          },
          py::arg("points"), py::arg("normals"), py::arg("keys"), py::arg("masks"), py::arg("samples"), py::arg("radius"),
          py::arg("falloff"), py::arg("method"), py::arg("seed"), py::arg("offset"), py::arg("sided"), py::arg("mask_mode"),
          py::arg("threads"), py::arg("isa"), py::arg("progress"))
      .def(
          "resolve_radius",
          [](PyScene& self, const py::object& radius) {
            const AoOptions options = read_options(128, radius, "constant", py::none(), py::none(), py::none(), "auto",
                                                   py::none(), 0, "auto");
            return to_engine(options).radius.resolve(self.scene().bounds().diagonal());
          },
          py::arg("radius") = "5%",
          "The AO radius in scene units for `radius` (a length, or a percentage of the bounding-box diagonal).");

  m.def("run_program", &run_program, py::arg("args"), py::arg("progress") = py::none());
  m.def("builtin_scenes", [] { return exao::builtin_scene_names(); });
  m.def("default_method", [] { return std::string(exao::engine::method_name(exao::engine::Options{}.method)); });
  m.def("_last_job", [] {
    std::lock_guard lock(g_record_mutex);
    py::dict d;
    d["done"] = g_last_job.done;
    d["total"] = g_last_job.total;
    d["cancelled"] = g_last_job.cancelled;
    return d;
  });
}
