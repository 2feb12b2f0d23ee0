#include "ucon/world/scenario_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <set>
#include <stdexcept>

namespace ucon {
namespace world {

namespace {

/// Thrown inside the parser only; converted to ScenarioError at the boundary.
struct ParseFailure {
  std::string key;
  std::string message;
};

std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

/// A mapping with its key path; remembers which keys were read to reject unknown ones.
class Map {
 public:
  Map(const YAML::Node& node, std::string path) : node_(node), path_(std::move(path)) {
    if (!node_.IsMap()) throw ParseFailure{path_, "expected a mapping"};
  }

  bool has(const std::string& key) const {
    const YAML::Node n = node_[key];
    return n && !n.IsNull();
  }

  YAML::Node get(const std::string& key) {
    used_.insert(key);
    const YAML::Node n = node_[key];
    if (!n || n.IsNull()) throw ParseFailure{join(path_, key), "missing key"};
    return n;
  }

  std::string path(const std::string& key) const { return join(path_, key); }

  double number(const std::string& key) { return toNumber(get(key), path(key)); }
  double number(const std::string& key, double def) { return has(key) ? number(key) : def; }

  std::string text(const std::string& key) {
    const YAML::Node n = get(key);
    if (!n.IsScalar()) throw ParseFailure{path(key), "expected a string"};
    return n.Scalar();
  }

  Vec2 vec2(const std::string& key) { return toVec2(get(key), path(key)); }

  void rejectUnknown() const {
    for (const auto& kv : node_) {
      const std::string k = kv.first.Scalar();
      if (!used_.count(k)) throw ParseFailure{path(k), "unknown key"};
    }
  }

  static double toNumber(const YAML::Node& n, const std::string& path) {
    if (!n.IsScalar()) throw ParseFailure{path, "expected a number"};
    const std::string& s = n.Scalar();
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size()) throw ParseFailure{path, "expected a number, got '" + s + "'"};
    if (!std::isfinite(v)) throw ParseFailure{path, "must be finite"};
    return v;
  }

  static Vec2 toVec2(const YAML::Node& n, const std::string& path) {
    if (!n.IsSequence() || n.size() != 2) throw ParseFailure{path, "expected [x, y]"};
    return Vec2(toNumber(n[0], path + "[0]"), toNumber(n[1], path + "[1]"));
  }

 private:
  YAML::Node node_;
  std::string path_;
  std::set<std::string> used_;
};

std::string indexed(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

StaticObstacle parseStatic(Map& m) {
  const std::string type = m.text("type");
  StaticObstacle o;
  if (type == "cylinder") {
    o.kind = ShapeKind::kCylinder;
    o.center = m.vec2("center");
    o.radius = m.number("radius");
    o.height = m.number("height");
  } else if (type == "box") {
    o.kind = ShapeKind::kBox;
    o.center = m.vec2("center");
    const Vec2 size = m.vec2("size");
    o.half_size = 0.5 * size;
    o.yaw = m.number("yaw", 0.0);
    o.height = m.number("height");
  } else if (type == "wall") {
    const Vec2 a = m.vec2("from"), b = m.vec2("to");
    const double thick = m.number("thickness");
    const double h = m.number("height");
    if (!((b - a).norm() > 0.0)) throw ParseFailure{m.path("to"), "wall has zero length"};
    if (!(thick > 0.0)) throw ParseFailure{m.path("thickness"), "must be > 0"};
    o = makeWall(a, b, thick, h);
  } else {
    throw ParseFailure{m.path("type"), "unknown static type '" + type + "' (cylinder|box|wall)"};
  }
  o.reflectivity = m.number("reflectivity", 100.0);
  m.rejectUnknown();
  return o;
}

MotionParams parseMotion(Map& m) {
  MotionParams p;
  const std::string type = m.text("type");
  if (type == "constant_velocity") {
    p.kind = MotionKind::kConstantVelocity;
    p.position = m.vec2("position");
    p.velocity = m.vec2("velocity");
  } else if (type == "constant_acceleration") {
    p.kind = MotionKind::kConstantAcceleration;
    p.position = m.vec2("position");
    p.velocity = m.vec2("velocity");
    p.acceleration = m.vec2("acceleration");
    p.speed_cap = m.number("speed_cap");
  } else if (type == "sinusoidal") {
    p.kind = MotionKind::kSinusoidal;
    p.position = m.vec2("position");
    p.amplitude = m.vec2("amplitude");
    p.omega = m.vec2("omega");
    p.phase = m.has("phase") ? m.vec2("phase") : Vec2::Zero();
    p.offset = m.vec2("offset");
  } else if (type == "pedestrian") {
    p.kind = MotionKind::kPedestrian;
    const YAML::Node w = m.get("waypoints");
    if (!w.IsSequence()) throw ParseFailure{m.path("waypoints"), "expected a list of [x, y]"};
    for (std::size_t i = 0; i < w.size(); ++i)
      p.waypoints.push_back(Map::toVec2(w[i], indexed(m.path("waypoints"), i)));
    const std::string mode = m.text("mode");
    if (mode == "loop")
      p.mode = PathMode::kLoop;
    else if (mode == "pingpong")
      p.mode = PathMode::kPingPong;
    else if (mode == "random")
      p.mode = PathMode::kRandom;
    else
      throw ParseFailure{m.path("mode"), "unknown mode '" + mode + "' (loop|pingpong|random)"};
    const Vec2 speed = m.vec2("speed");
    p.speed_min = speed[0];
    p.speed_max = speed[1];
    const Vec2 change = m.vec2("speed_change_interval");
    p.speed_change_min_s = change[0];
    p.speed_change_max_s = change[1];
    p.pause_probability = m.number("pause_probability");
    const Vec2 pause = m.vec2("pause");
    p.pause_min_s = pause[0];
    p.pause_max_s = pause[1];
    p.jitter = m.number("jitter", 0.0);
  } else {
    throw ParseFailure{m.path("type"),
                       "unknown motion type '" + type +
                           "' (constant_velocity|constant_acceleration|sinusoidal|pedestrian)"};
  }
  m.rejectUnknown();
  return p;
}

Scenario parseRoot(const YAML::Node& root) {
  Map m(root, "");
  Scenario s;
  s.name = m.text("name");
  if (m.has("seed")) {
    const double seed = m.number("seed");
    if (seed < 0 || seed != std::floor(seed) || seed > 9.0e15) throw ParseFailure{"seed", "must be a non-negative integer"};
    s.seed = static_cast<uint64_t>(seed);
  }
  s.duration_s = m.number("duration");
  {
    Map b(m.get("bounds"), "bounds");
    s.bounds.xmin = b.number("xmin");
    s.bounds.xmax = b.number("xmax");
    s.bounds.ymin = b.number("ymin");
    s.bounds.ymax = b.number("ymax");
    b.rejectUnknown();
  }
  {
    Map r(m.get("robot"), "robot");
    s.robot.start = r.vec2("start");
    s.robot.start_yaw = r.number("yaw");
    s.robot.radius = r.number("radius");
    s.robot.max_speed = r.number("max_speed");
    s.robot.max_accel = r.number("max_accel");
    const YAML::Node g = r.get("goals");
    if (!g.IsSequence()) throw ParseFailure{"robot.goals", "expected a list of [x, y]"};
    for (std::size_t i = 0; i < g.size(); ++i)
      s.robot.goals.push_back(Map::toVec2(g[i], indexed("robot.goals", i)));
    r.rejectUnknown();
  }
  if (m.has("static")) {
    const YAML::Node st = m.get("static");
    if (!st.IsSequence()) throw ParseFailure{"static", "expected a list"};
    for (std::size_t i = 0; i < st.size(); ++i) {
      Map o(st[i], indexed("static", i));
      s.statics.push_back(parseStatic(o));
    }
  }
  if (m.has("moving")) {
    const YAML::Node mv = m.get("moving");
    if (!mv.IsSequence()) throw ParseFailure{"moving", "expected a list"};
    for (std::size_t i = 0; i < mv.size(); ++i) {
      const std::string path = indexed("moving", i);
      Map o(mv[i], path);
      MovingObstacle mo;
      const double id = o.number("id");
      if (id != std::floor(id) || id < 1 || id > 9.0e15) throw ParseFailure{o.path("id"), "must be an integer > 0"};
      mo.id = static_cast<int64_t>(id);
      mo.radius = o.number("radius");
      mo.height = o.number("height");
      mo.reflectivity = o.number("reflectivity", 60.0);
      Map mm(o.get("motion"), o.path("motion"));
      mo.motion = parseMotion(mm);
      o.rejectUnknown();
      s.movers.push_back(mo);
    }
  }
  m.rejectUnknown();
  return s;
}

}  // namespace

std::string ScenarioError::toString() const {
  std::string s = key.empty() ? "scenario error: " + message
                              : "scenario error at '" + key + "': " + message;
  if (!source.empty()) s += " (in " + source + ")";
  return s;
}

std::optional<Scenario> parseScenarioYaml(const std::string& text, const std::string& source,
                                          ScenarioError* error) {
  auto fail = [&](const std::string& key, const std::string& msg) -> std::optional<Scenario> {
    if (error) *error = ScenarioError{key, msg, source};
    return std::nullopt;
  };
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return fail("", std::string("YAML syntax: ") + e.what());
  }
  Scenario s;
  try {
    s = parseRoot(root);
  } catch (const ParseFailure& f) {
    return fail(f.key, f.message);
  } catch (const YAML::Exception& e) {
    return fail("", std::string("YAML: ") + e.what());
  }
  if (auto bad = validate(s)) {
    const auto colon = bad->find(": ");
    if (colon == std::string::npos) return fail("", *bad);
    return fail(bad->substr(0, colon), bad->substr(colon + 2));
  }
  return s;
}

std::optional<ScenarioSpec> parseScenarioSpec(const std::string& spec, std::string* error) {
  ScenarioSpec out;
  if (spec == "pedestrians" || spec == "crossing" || spec == "corridor" || spec == "hall") {
    out.kind = ScenarioSpec::Kind::kBuiltin;
    out.name = spec;
    return out;
  }
  if (spec.rfind("bench:", 0) == 0) {
    const std::string rest = spec.substr(6);
    const auto colon = rest.find(':');
    auto bad = [&]() -> std::optional<ScenarioSpec> {
      if (error) *error = "bad scenario '" + spec + "': expected bench:<N_d>:<seed>, N_d in 0..2000, seed >= 0";
      return std::nullopt;
    };
    if (colon == std::string::npos) return bad();
    const std::string a = rest.substr(0, colon), b = rest.substr(colon + 1);
    auto isDigits = [](const std::string& x) {
      if (x.empty() || x.size() > 18) return false;
      for (char c : x)
        if (c < '0' || c > '9') return false;
      return true;
    };
    if (!isDigits(a) || !isDigits(b)) return bad();
    const long long n = std::stoll(a);
    if (n > 2000) return bad();
    out.kind = ScenarioSpec::Kind::kBench;
    out.name = spec;
    out.num_moving = static_cast<int>(n);
    out.seed = static_cast<uint64_t>(std::stoull(b));
    return out;
  }
  if (spec.empty()) {
    if (error) *error = "empty scenario name";
    return std::nullopt;
  }
  out.kind = ScenarioSpec::Kind::kFile;
  out.name = spec;
  return out;
}

}  // namespace world
}  // namespace ucon
