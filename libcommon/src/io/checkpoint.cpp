// The /checkpoint group of a partial run (checkpoint.hpp; docs/method.md, "Checkpoints").
#include "cdpile/io/checkpoint.hpp"

#include "cdpile/error.hpp"
#include "cdpile/io/products.hpp"

#include <cmath>
#include <filesystem>

namespace cdpile::io {

namespace {
// Attributes of the group that are not counters.
bool is_counter(const std::string& name) {
  return name != "step" && name != "time" && name != "description";
}

const Value* find(const Checkpoint& c, const std::string& name) {
  for (const auto& [n, v] : c.counters)
    if (n == name) return &v;
  return nullptr;
}
}  // namespace

bool Checkpoint::has_counter(const std::string& name) const { return find(*this, name) != nullptr; }

std::int64_t Checkpoint::counter_int(const std::string& name, const std::string& file) const {
  const Value* v = find(*this, name);
  if (!v || !std::holds_alternative<std::int64_t>(*v))
    throw Error(file, kCheckpointGroup, "no integer attribute '" + name + "'");
  return std::get<std::int64_t>(*v);
}

double Checkpoint::counter_real(const std::string& name, const std::string& file) const {
  const Value* v = find(*this, name);
  if (!v || !std::holds_alternative<double>(*v))
    throw Error(file, kCheckpointGroup, "no real attribute '" + name + "'");
  return std::get<double>(*v);
}

void write_checkpoint(const h5::File& f, const Checkpoint& c) {
  const std::string g = kCheckpointGroup;
  if (h5::exists(f, g)) h5::remove(f, g);
  h5::create_group(f, g);
  const Grains& s = c.grains;
  const auto n = static_cast<hsize_t>(s.size());
  h5::write(f, g + "/position", s.position.empty() ? nullptr : s.position[0].data(), {n, 2});
  h5::write(f, g + "/velocity", s.velocity.empty() ? nullptr : s.velocity[0].data(), {n, 2});
  h5::write(f, g + "/orientation", s.orientation);
  h5::write(f, g + "/angular_velocity", s.angular_velocity);
  std::vector<std::int32_t> ii, jj;
  std::vector<double> rn, rt;
  for (const auto& imp : c.impulses) {
    ii.push_back(imp.i);
    jj.push_back(imp.j);
    rn.push_back(imp.rn);
    rt.push_back(imp.rt);
  }
  h5::write(f, g + "/impulse_i", ii);
  h5::write(f, g + "/impulse_j", jj);
  h5::write(f, g + "/impulse_rn", rn);
  h5::write(f, g + "/impulse_rt", rt);
  h5::set_attr(f, g, "step", c.step);
  h5::set_attr(f, g, "time", c.time);
  for (const auto& [name, value] : c.counters)
    std::visit([&, &name = name](const auto& v) { h5::set_attr(f, g, name, v); }, value);
  h5::set_attr(f, g, "description", c.description);
}

Checkpoint read_checkpoint(const h5::File& f, const Grains& properties) {
  const std::string g = kCheckpointGroup;
  if (!h5::exists(f, g)) throw Error(f.name(), g, "missing: not a partial run");
  const auto n = static_cast<hsize_t>(properties.size());
  Checkpoint c;
  c.grains = properties;
  auto pos = h5::read<double>(f, g + "/position", {n, 2});
  auto vel = h5::read<double>(f, g + "/velocity", {n, 2});
  c.grains.orientation = h5::read<double>(f, g + "/orientation", {n});
  c.grains.angular_velocity = h5::read<double>(f, g + "/angular_velocity", {n});
  if (pos.size() != 2 * n || vel.size() != 2 * n || c.grains.orientation.size() != n ||
      c.grains.angular_velocity.size() != n)
    throw Error(f.name(), g, "grain state does not match the " + std::to_string(n) + " grains");
  for (std::size_t k = 0; k < n; ++k) {
    c.grains.position[k] = Vec2(pos[2 * k], pos[2 * k + 1]);
    c.grains.velocity[k] = Vec2(vel[2 * k], vel[2 * k + 1]);
  }
  auto ii = h5::read<std::int32_t>(f, g + "/impulse_i", {h5::any});
  auto jj = h5::read<std::int32_t>(f, g + "/impulse_j", {ii.size()});
  auto rn = h5::read<double>(f, g + "/impulse_rn", {ii.size()});
  auto rt = h5::read<double>(f, g + "/impulse_rt", {ii.size()});
  for (std::size_t k = 0; k < ii.size(); ++k) c.impulses.push_back({ii[k], jj[k], rn[k], rt[k]});
  c.step = h5::attr_int(f, g, "step");
  c.time = h5::attr_double(f, g, "time");
  // As a frame's step and time (docs/schema.md, "Ranges"): the step an integer of [0, 2^53].
  if (c.step < 0 || c.step > (std::int64_t{1} << 53))
    throw Error(f.name(), g,
                "attribute 'step': " + std::to_string(c.step) + " is outside [0, 2^53]");
  if (!(c.time >= 0))
    throw Error(f.name(), g, "attribute 'time': " + format_number(c.time) + " s is outside [0, inf) s");
  for (const std::string& name : h5::attr_names(f, g)) {
    if (!is_counter(name)) continue;
    switch (h5::attr_class(f, g, name)) {
      case H5T_INTEGER: {
        // Counters are steps, counts and flags, and the sub-step level a shift count
        // (docs/schema.md, "Ranges"): within 2^53, the level within [0, 30].
        const std::int64_t v = h5::attr_int(f, g, name);
        const std::int64_t top = name == "substep_level" ? 30 : std::int64_t{1} << 53;
        const std::int64_t bottom = name == "substep_level" ? 0 : -top;
        if (v < bottom || v > top)
          throw Error(f.name(), g,
                      "attribute '" + name + "': " + std::to_string(v) + " is outside " +
                          (top == 30 ? "[0, 30]" : "[-2^53, 2^53]"));
        c.counters.emplace_back(name, v);
        break;
      }
      case H5T_FLOAT: c.counters.emplace_back(name, h5::attr_double(f, g, name)); break;
      default: c.counters.emplace_back(name, h5::attr_string(f, g, name)); break;
    }
  }
  return c;
}

std::string run_or_partial(const std::string& path) {
  std::error_code ec;
  if (path == "-" || std::filesystem::exists(path, ec)) return path;
  const std::string partial = path + ".partial";
  return std::filesystem::exists(partial, ec) ? partial : path;
}

std::string partial_run_note(const RunReader& run) {
  if (!h5::exists(run.file(), kCheckpointGroup)) return "";
  const std::size_t F = run.frame_count();
  std::string held = std::to_string(F) + " frames";
  if (F > 0)
    held += ", the last at step " + std::to_string(run.frame_steps().back()) + ", tilt " +
            format_number(std::round(run.frame_tilt_angle(F - 1) * 180.0 / M_PI * 1e6) / 1e6) +
            " deg";
  return run.name() +
         ": a partial run (tilt-cd has not finished it: still running, or stopped): read up to "
         "its last checkpoint, " +
         held;
}

}  // namespace cdpile::io
