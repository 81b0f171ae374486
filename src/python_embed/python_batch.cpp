// A Python controller's batch: the class's instance sees the core's sensor arrays and writes the command
// arrays through numpy views (no copies), once per tick, on the calling thread with the GIL held. What it
// writes is checked before the world sees it; the status is counted here, as ForagerBatch counts it.
#include <algorithm>
#include <cmath>

#include "embedded.hpp"
#include "swarm_forage/core/controllers/forage_common.hpp"
#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {
// Hidden, as pybind11's own namespace: these types hold Python objects.
#pragma GCC visibility push(hidden)
namespace embedded {

namespace {

// A view of n values at data, read-only unless writable, kept alive by `owner` (never copied).
template <class T>
py::array view(const T* data, std::size_t n, const py::handle& owner, bool writable) {
  static const T none{};
  const void* at = data != nullptr ? static_cast<const void*>(data) : &none;  // an empty vector's null data
  py::array a(py::dtype::of<T>(), {n}, {sizeof(T)}, at, owner);
  if (!writable) py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

// A read-only (rows, columns) view of a row-major table.
py::array table(const double* data, std::size_t rows, std::size_t columns, const py::handle& owner) {
  static const double none = 0;
  const void* at = data != nullptr ? static_cast<const void*>(data) : &none;
  py::array a(py::dtype::of<double>(), {rows, columns}, {columns * sizeof(double), sizeof(double)}, at,
              owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

std::string wheel(float v) {
  return std::isnan(v) ? "nan" : std::isinf(v) ? (v > 0 ? "inf" : "-inf") : canonicalNumber(v);
}

}  // namespace

class PythonBatch final : public ControllerBatch {
 public:
  PythonBatch(std::shared_ptr<PythonClass> cls, const ControllerConfigs& configs, uint32_t seed,
              uint32_t first, uint32_t count)
      : cls_(std::move(cls)),
        first_(first),
        count_(count),
        keys_(count),
        uniform_(std::size_t{count} * cls_->draws),
        normal_(std::size_t{count} * cls_->normals),
        state_(count, 0),
        avoiding_(count, 0),
        ones_(count, 1),
        stalls_(count) {
    for (uint32_t l = 0; l < count; ++l)
      keys_[l] = CounterRng::idKey(seed, RngStream::kController, first + l);
    py::gil_scoped_acquire hold;
    try {
      start(configs, seed, first, count);
    } catch (...) {
      py_.reset();  // with the GIL: the destructor does not run for a constructor that throws
      throw;
    }
  }

  ~PythonBatch() override {
    py::gil_scoped_acquire hold;
    py_.reset();
  }

  std::string name() const override { return cls_->kind; }
  bool checkpointable() const override { return cls_->checkpointable; }

  void step(uint64_t tick, const SensorData& s, CommandData& out, ControllerStatus& status) override {
    out.first_id = first_;
    if (out.size() != count_) out.resize(count_);
    draw(tick);
    for (uint32_t l = 0; l < count_; ++l) avoiding_[l] = s.threatened[first_ + l];
    {
      py::gil_scoped_acquire hold;
      bindSensors(s);
      bindCommands(out);
      try {
        py_->step(tick, py_->s, py_->out);
      } catch (const py::error_already_set& e) {
        throw std::runtime_error(cls_->named() + " raised in step: " + lastLine(e));
      }
      readBack();
    }
    count(tick, s, out, status);
  }

  // The status counts' state and stall trackers, then the class's own state: save() -> {name: array}, each
  // kept as its dtype, shape and bytes; load() gets the same arrays back.
  void persist(StateArchive& a) override {
    if (!cls_->checkpointable)
      throw CheckpointError("controller '" + cls_->kind + "' cannot be checkpointed: " + cls_->named() +
                            " defines no save(self) and load(self, arrays)");
    a.section("python controller");
    a.io(state_);
    for (uint32_t l = 0; l < count_; ++l) stalls_.persist(a, l);
    py::gil_scoped_acquire hold;
    try {
      const py::module_ np = py::module_::import("numpy");
      if (a.loading()) {
        uint64_t n = 0;
        a.io(n);
        py::dict arrays;
        for (uint64_t k = 0; k < n; ++k) {
          std::string name, dtype, bytes;
          std::vector<uint64_t> shape;
          a.io(name, dtype, shape, bytes);
          py::tuple dims(shape.size());
          for (std::size_t d = 0; d < shape.size(); ++d) dims[d] = py::int_(shape[d]);
          arrays[py::str(name)] = np.attr("frombuffer")(py::bytes(bytes), py::arg("dtype") = dtype)
                                      .attr("reshape")(dims)
                                      .attr("copy")();
        }
        py_->instance.attr("load")(arrays);
        return;
      }
      const py::object saved = py_->instance.attr("save")();
      if (!py::isinstance<py::dict>(saved))
        throw CheckpointError(cls_->named() + ": save() must return a dict of numpy arrays (got " +
                              py::repr(py::type::of(saved)).cast<std::string>() + ")");
      std::vector<std::string> names;
      for (const auto& item : py::reinterpret_borrow<py::dict>(saved)) {
        if (!py::isinstance<py::str>(item.first))
          throw CheckpointError(cls_->named() + ": save()'s keys must be strings (got " +
                                py::repr(item.first).cast<std::string>() + ")");
        names.push_back(item.first.cast<std::string>());
      }
      std::sort(names.begin(), names.end());
      uint64_t n = names.size();
      a.io(n);
      for (std::string& name : names) {
        const py::array v = np.attr("ascontiguousarray")(saved[py::str(name)]);
        const char kind = v.dtype().kind();
        if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f')
          throw CheckpointError(cls_->named() + ": save()['" + name + "'] has dtype " +
                                py::str(v.dtype()).cast<std::string>() +
                                "; valid: bool, integer or float arrays");
        std::string dtype = py::str(v.dtype().attr("str")).cast<std::string>();
        std::vector<uint64_t> shape;
        for (py::ssize_t d = 0; d < v.ndim(); ++d) shape.push_back(static_cast<uint64_t>(v.shape(d)));
        std::string bytes = v.attr("tobytes")().cast<std::string>();
        a.io(name, dtype, shape, bytes);
      }
    } catch (const py::error_already_set& e) {
      throw CheckpointError(cls_->named() + " raised in " + (a.loading() ? "load" : "save") + ": " +
                            lastLine(e));
    }
  }

 private:
  // The instance and the namespaces it is handed, made with the GIL held.
  void start(const ControllerConfigs& configs, uint32_t seed, uint32_t first, uint32_t count) {
    const PyConstants& constants = configs.of<PyConstants>(cls_->kind);
    py_ = std::make_unique<Py>();
    py_->owner = py::capsule(this, [](void*) {});
    py::dict world;
    WorldFacts facts{Vec2(0, 0), LineOfSight{}};  // before the run has a world: the origin
    if (configs.world) facts = *configs.world;
    world["nest_x"] = facts.nest_center.x();
    world["nest_y"] = facts.nest_center.y();
    world["los_cell"] = facts.sight.cell;
    world["los_radius"] = facts.sight.radius;
    py::list quirks;
    std::string names = configs.quirks.controllerSide().names();
    for (std::size_t at = 0; !names.empty() && at != std::string::npos;) {
      const std::size_t comma = names.find(',', at);
      quirks.append(names.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
      at = comma == std::string::npos ? comma : comma + 1;
    }
    world["quirks"] = quirks;
    try {
      py_->instance = cls_->cls(constants.asDict(), seed, first, count, world);
      py_->step = py_->instance.attr("step");
    } catch (const py::error_already_set& e) {
      throw std::runtime_error(cls_->named() + " raised in __init__: " + lastLine(e));
    }
    const py::module_ types = py::module_::import("types");
    py_->s = types.attr("SimpleNamespace")(py::arg("first_id") = first, py::arg("count") = count);
    py_->out = types.attr("SimpleNamespace")();
  }

  struct Py {
    py::object owner, instance, step, s, out;
    std::vector<const void*> sensors_bound;
    const void* commands_bound = nullptr;
    py::array left, right, request, state, avoiding;
  };

  // The class's draws of this tick: uniform[l, j] is draw j + 1 of robot l's generator (seed, robot, tick),
  // normal[l, k] Box-Muller on the two after them, so the bits never depend on Python.
  void draw(uint64_t tick) {
    const uint32_t d = cls_->draws, g = cls_->normals;
    if (d == 0 && g == 0) return;
    for (uint32_t l = 0; l < count_; ++l) {
      CounterRng rng = CounterRng::atTick(keys_[l], tick);
      for (uint32_t j = 0; j < d; ++j) uniform_[std::size_t{l} * d + j] = rng.uniform();
      for (uint32_t k = 0; k < g; ++k) normal_[std::size_t{l} * g + k] = rng.gaussian();
    }
  }

  // The sensor views, made again only when the world's arrays moved; line of sight every tick (its size
  // does).
  void bindSensors(const SensorData& s) {
    const std::vector<const void*> now = {
        s.x.data(),          s.y.data(),          s.theta.data(),         s.threatened.data(),
        s.obstacle_x.data(), s.obstacle_y.data(), s.light_x.data(),       s.light_y.data(),
        s.ground.data(),     s.events.data(),     s.carried_block.data(), s.active.data()};
    const py::handle o = py_->owner;
    py::object ns = py_->s;
    const std::size_t f = first_, n = count_;
    if (now != py_->sensors_bound) {
      ns.attr("x") = view(s.x.data() + f, n, o, false);
      ns.attr("y") = view(s.y.data() + f, n, o, false);
      ns.attr("theta") = view(s.theta.data() + f, n, o, false);
      ns.attr("threatened") = view(s.threatened.data() + f, n, o, false);
      ns.attr("obstacle_x") = view(s.obstacle_x.data() + f, n, o, false);
      ns.attr("obstacle_y") = view(s.obstacle_y.data() + f, n, o, false);
      ns.attr("light_x") = view(s.light_x.data() + f, n, o, false);
      ns.attr("light_y") = view(s.light_y.data() + f, n, o, false);
      ns.attr("ground") = view(s.ground.data() + f, n, o, false);
      ns.attr("events") = view(s.events.data() + f, n, o, false);
      ns.attr("carried_block") = view(s.carried_block.data() + f, n, o, false);
      ns.attr("active") = view(s.active.empty() ? ones_.data() : s.active.data() + f, n, o, false);
      ns.attr("uniform") = table(uniform_.data(), n, cls_->draws, o);
      ns.attr("normal") = table(normal_.data(), n, cls_->normals, o);
      py_->sensors_bound = now;
    }
    if (!cls_->line_of_sight) return;
    const bool seen = s.hasLineOfSight();
    ns.attr("los_block_offset") =
        view(seen ? s.los_block_offset.data() + f : nullptr, seen ? n + 1 : 0, o, false);
    ns.attr("los_block_id") = view(s.los_block_id.data(), s.los_block_id.size(), o, false);
    ns.attr("los_block_x") = view(s.los_block_x.data(), s.los_block_x.size(), o, false);
    ns.attr("los_block_y") = view(s.los_block_y.data(), s.los_block_y.size(), o, false);
    ns.attr("los_cache_offset") =
        view(seen ? s.los_cache_offset.data() + f : nullptr, seen ? n + 1 : 0, o, false);
    ns.attr("los_cache_id") = view(s.los_cache_id.data(), s.los_cache_id.size(), o, false);
    ns.attr("los_cache_x") = view(s.los_cache_x.data(), s.los_cache_x.size(), o, false);
    ns.attr("los_cache_y") = view(s.los_cache_y.data(), s.los_cache_y.size(), o, false);
    ns.attr("los_cache_blocks") = view(s.los_cache_blocks.data(), s.los_cache_blocks.size(), o, false);
  }

  void bindCommands(CommandData& out) {
    Py& p = *py_;
    if (p.commands_bound != out.left.data()) {
      p.left = view(out.left.data(), count_, p.owner, true);
      p.right = view(out.right.data(), count_, p.owner, true);
      p.request = view(out.request.data(), count_, p.owner, true);
      p.state = view(state_.data(), count_, p.owner, true);
      p.avoiding = view(avoiding_.data(), count_, p.owner, true);
      p.commands_bound = out.left.data();
    }
    p.out.attr("left") = p.left;
    p.out.attr("right") = p.right;
    p.out.attr("request") = p.request;
    p.out.attr("state") = p.state;
    p.out.attr("avoiding") = p.avoiding;
  }

  // An attribute of `out` the class replaced instead of writing into: taken when it has the shape and dtype
  // of the view it replaced, refused otherwise.
  void readBack() {
    Py& p = *py_;
    const std::pair<const char*, py::array*> fields[] = {{"left", &p.left},
                                                         {"right", &p.right},
                                                         {"request", &p.request},
                                                         {"state", &p.state},
                                                         {"avoiding", &p.avoiding}};
    for (const auto& [field, target] : fields) {
      const py::object got = p.out.attr(field);
      if (got.is(*target)) continue;
      const std::string want =
          "(" + std::to_string(count_) + ",) " + py::str(target->dtype()).cast<std::string>();
      std::string had = py::repr(py::type::of(got)).cast<std::string>();
      if (py::isinstance<py::array>(got)) {
        const auto a = py::reinterpret_borrow<py::array>(got);
        std::string shape;
        for (py::ssize_t k = 0; k < a.ndim(); ++k) shape += std::to_string(a.shape(k)) + ",";
        had = "(" + shape + ") " + py::str(a.dtype()).cast<std::string>();
        if (a.ndim() == 1 && a.shape(0) == static_cast<py::ssize_t>(count_) &&
            a.dtype().is(target->dtype())) {
          (*target)[py::slice(0, count_, 1)] = a;  // the same shape and dtype: copied into the core's array
          continue;
        }
      }
      throw std::runtime_error(cls_->named() + " set out." + field + " to an array " + had + "; it must be " +
                               want + ": write into it (out." + field + "[:] = ...)");
    }
  }

  // Checks what the class wrote and counts the status; a robot out of the swarm is stopped and not counted.
  void count(uint64_t tick, const SensorData& s, CommandData& out, ControllerStatus& status) {
    status.in_avoidance = 0;
    status.stalled = 0;
    status.tasks = TaskCounts{};
    status.state_names = cls_->states;
    status.state_counts.assign(cls_->states.size(), 0);
    const auto stalls = stalls_.arrays();
    for (uint32_t l = 0; l < count_; ++l) {
      const uint32_t i = first_ + l;
      out.task[l] = kTaskNone;
      if (!s.isActive(i)) {
        out.left[l] = out.right[l] = 0.f;
        out.request[l] = kNone;
        continue;
      }
      if (s.events[i] & kJoined) stalls_.forget(l);
      const bool finite = std::isfinite(out.left[l]) && std::isfinite(out.right[l]);
      if (!finite || out.request[l] > kCacheDrop || state_[l] >= cls_->states.size()) refuse(l, tick, out);
      ++status.state_counts[state_[l]];
      status.in_avoidance += avoiding_[l] != 0 ? 1 : 0;
      status.stalled += stalls.stalled(l, s.x[i], s.y[i], tick) ? 1 : 0;
    }
  }

  // What robot l's command or state has wrong, as the run's stop reason (built only then: count() runs for
  // every robot and tick).
  [[noreturn]] void refuse(uint32_t l, uint64_t tick, const CommandData& out) const {
    const std::string robot =
        " for robot " + std::to_string(first_ + l) + " (tick " + std::to_string(tick) + ")";
    if (!std::isfinite(out.left[l]) || !std::isfinite(out.right[l]))
      throw std::runtime_error(cls_->named() + " wrote the wheel speeds left " + wheel(out.left[l]) +
                               ", right " + wheel(out.right[l]) + robot + "; they must be finite (m/s)");
    if (out.request[l] > kCacheDrop)
      throw std::runtime_error(cls_->named() + " wrote the request code " + std::to_string(out.request[l]) +
                               robot + "; valid: 0 none, 1 pickup, 2 drop, 3 cache pickup, 4 cache drop");
    throw std::runtime_error(cls_->named() + " wrote the state " + std::to_string(state_[l]) + robot +
                             "; valid: 0 to " + std::to_string(cls_->states.size() - 1) + " (its states)");
  }

  std::shared_ptr<PythonClass> cls_;
  uint32_t first_, count_;
  std::vector<uint64_t> keys_;
  std::vector<double> uniform_, normal_;
  std::vector<uint8_t> state_, avoiding_, ones_;
  StallTracker stalls_;
  std::unique_ptr<Py> py_;
};

std::unique_ptr<ControllerBatch> makePythonBatch(const std::shared_ptr<PythonClass>& cls,
                                                 const ControllerConfigs& configs, uint32_t seed,
                                                 uint32_t first_id, uint32_t count) {
  return std::make_unique<PythonBatch>(cls, configs, seed, first_id, count);
}

}  // namespace embedded
#pragma GCC visibility pop
}  // namespace swarm_forage
