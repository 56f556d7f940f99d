// Checkpoint files. See checkpoint_file.h.
#include "virtual_triaxial/io/checkpoint_file.h"

#include <stdexcept>

#include "virtual_triaxial/io/hdf5_atomic_file.h"
#include "virtual_triaxial/io/sample_file.h"

namespace vt::io {

namespace {

void write_numbers(const h5::Group& g, const std::string& name, const std::vector<double>& v) {
  if (!v.empty()) g.write(name, v, v.size(), 0, "1");
}

std::vector<double> read_numbers(const h5::Group& g, const std::string& name) {
  if (!g.has(name)) return {};
  return g.read<double>(name, g.rows(name), 0);
}

}  // namespace

void write_checkpoint(const std::string& path, const CheckpointFile& c) {
  h5::AtomicFile file(path);
  {
    SampleMetadata meta;
    meta.software_version = "virtual_triaxial 0.1.0";
    meta.created_by = "checkpoint of " + c.scene_path;
    meta.description = "run checkpoint: stage " + std::to_string(c.run.stage_index) + ", stage step " +
                       std::to_string(c.run.stage_steps);
    write_sample_into(file.root(), c.state, meta);
    const h5::Group g = file.root().create_group("checkpoint");
    const protocol::RunCheckpoint& r = c.run;
    g.set_attr("format", kCheckpointFormat);
    g.set_attr("format_version", kCheckpointFormatVersion);
    g.set_attr("scene_path", c.scene_path);
    g.set_attr("scene_text", c.scene_text);
    g.set_attr("results_rows", c.results_rows);
    g.set_attr("stage_index", static_cast<std::int64_t>(r.stage_index));
    g.set_attr("stage_steps", r.stage_steps);
    g.set_attr("steps", r.steps);
    g.set_attr("ticks", r.ticks);
    g.set_attr("wall_seconds", r.wall_seconds);
    g.set_attr("servo", static_cast<std::int64_t>(r.servo ? 1 : 0));
    g.set_attr("servo_start_time", r.servo_start_time);
    g.set_attr("specimen_void_ratio", r.specimen.void_ratio);
    g.set_attr("specimen_dispersity_index", r.specimen.dispersity_index);
    if (r.rig_tick > 0) g.set_attr("rig_tick", static_cast<std::int64_t>(r.rig_tick));
    if (r.lockstep_timeouts > 0) g.set_attr("lockstep_timeouts", r.lockstep_timeouts);
    g.set_attr("finished", static_cast<std::int64_t>(r.finished.size()));
    for (std::size_t i = 0; i < r.finished.size(); ++i) {
      const std::string k = "finished_" + std::to_string(i) + "_";
      g.set_attr(k + "name", r.finished[i].name);
      g.set_attr(k + "type", static_cast<std::int64_t>(r.finished[i].type));
      g.set_attr(k + "steps", r.finished[i].steps);
      g.set_attr(k + "stop_reason", r.finished[i].stop_reason);
    }
    g.write("rates", std::vector<double>(r.rates, r.rates + 3), 3, 0, "1/s");
    write_numbers(g, "servo_memory", r.servo_memory);
    write_numbers(g, "rate_strategy", r.judge.rate_strategy);
    write_numbers(g, "rate_controller_memory", r.rate_controller_memory);
    const h5::Group j = g.create_group("judge");
    for (const auto& [name, value] : protocol::to_fields(r.judge)) j.set_attr(name, value);
  }
  file.commit();
}

CheckpointFile read_checkpoint(const std::string& path) {
  const h5::Group root = h5::Group::open_file_read(path);
  if (!root.has("checkpoint")) root.fail("checkpoint", "missing (not a checkpoint file)");
  const h5::Group g = root.open_group("checkpoint");
  if (!g.has_attr("format") || g.attr_string("format") != kCheckpointFormat)
    root.fail("checkpoint", "format: not a virtual_triaxial checkpoint");
  if (g.attr_int("format_version") != kCheckpointFormatVersion)
    root.fail("checkpoint", "format_version: " + std::to_string(g.attr_int("format_version")) + " not supported");
  CheckpointFile c;
  c.state = read_sample_from(root);
  c.scene_path = g.attr_string("scene_path");
  c.scene_text = g.attr_string("scene_text");
  c.results_rows = g.attr_int("results_rows");
  protocol::RunCheckpoint& r = c.run;
  r.stage_index = static_cast<std::size_t>(g.attr_int("stage_index"));
  r.stage_steps = g.attr_int("stage_steps");
  r.steps = g.attr_int("steps");
  r.ticks = g.attr_int("ticks");
  r.wall_seconds = g.attr_double("wall_seconds");
  r.servo = g.attr_int("servo") != 0;
  r.servo_start_time = g.attr_double("servo_start_time");
  r.specimen.void_ratio = g.attr_double("specimen_void_ratio");
  r.specimen.dispersity_index = g.attr_double("specimen_dispersity_index");
  if (g.has_attr("rig_tick")) r.rig_tick = static_cast<std::uint64_t>(g.attr_int("rig_tick"));
  if (g.has_attr("lockstep_timeouts")) r.lockstep_timeouts = g.attr_int("lockstep_timeouts");
  const std::int64_t finished = g.attr_int("finished");
  for (std::int64_t i = 0; i < finished; ++i) {
    const std::string k = "finished_" + std::to_string(i) + "_";
    protocol::StageOutcome o;
    o.name = g.attr_string(k + "name");
    o.type = static_cast<protocol::StageType>(g.attr_int(k + "type"));
    o.steps = g.attr_int(k + "steps");
    o.stop_reason = g.attr_string(k + "stop_reason");
    r.finished.push_back(o);
  }
  const std::vector<double> rates = g.read<double>("rates", 3, 0);
  for (int i = 0; i < 3; ++i) r.rates[i] = rates[static_cast<std::size_t>(i)];
  r.servo_memory = read_numbers(g, "servo_memory");
  r.rate_controller_memory = read_numbers(g, "rate_controller_memory");
  const h5::Group j = g.open_group("judge");
  std::map<std::string, double> fields;
  for (const std::string& name : j.attr_names()) fields[name] = j.attr_double(name);
  try {
    r.judge = protocol::from_fields(fields, read_numbers(g, "rate_strategy"));
  } catch (const std::invalid_argument& e) {
    root.fail("checkpoint/judge", e.what());
  }
  return c;
}

}  // namespace vt::io
