#include "pipeline/run_provenance.h"

#include <algorithm>
#include <set>

#include "core/check.h"
#include "label/depth_exr.h"
#include "pipeline/content_hash.h"
#include "pipeline/json_read.h"
#include "render/mesh_closure.h"
#include "session/manifest.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

template <typename Object>
std::vector<InputSpec> Meshes(const std::vector<Object>& objects) {
  std::vector<InputSpec> inputs;
  for (const Object& o : objects) inputs.push_back({"mesh:" + o.name, o.mesh_path, false, {}});
  return inputs;
}

}  // namespace

InputSpec SessionInput(const fs::path& session_dir) {
  InputSpec spec{"session", fs::absolute(session_dir).lexically_normal(), true, {}};
  for (const fs::path& file : SessionStreamFiles(LoadManifest(session_dir))) spec.members.push_back(file.generic_string());
  return spec;
}

std::vector<InputSpec> MeshInputs(const std::vector<LabelObject>& objects) { return Meshes(objects); }
std::vector<InputSpec> MeshInputs(const std::vector<ValidationObject>& objects) { return Meshes(objects); }

InputSpec RunFolderInput(const std::string& role, const fs::path& dir) {
  return {role, fs::absolute(dir).lexically_normal(), true, {}};
}

nlohmann::json ToJson(const LabelOptions& o) {
  return {{"cameras", o.cameras},
          {"frame_begin", o.frame_begin},
          {"frame_end", o.frame_end},
          {"output", {{"write_depth", o.output.write_depth},
                      {"depth_compression", DepthCompressionName(o.output.depth_compression)},
                      {"write_masks", o.output.write_masks},
                      {"write_bop_masks", o.output.write_bop_masks},
                      {"write_overlay", o.output.write_overlay}}},
          {"max_gap_ns", o.chain.interpolation.max_gap_ns},
          {"speed_half_window_ns", o.chain.speed_half_window_ns},
          {"fast_motion_m_per_s", o.chain.fast_motion_m_per_s},
          {"fast_motion_deg_per_s", o.chain.fast_motion_deg_per_s},
          {"visibility", {{"rule", ToString(o.visibility.rule)}, {"hole_colour", o.visibility.hole_colour},
                          {"delta_base_m", o.visibility.delta_base_m}, {"noise_sigmas", o.visibility.noise_sigmas},
                          {"noise_coeff_per_m", o.visibility.noise_coeff_per_m}}},
          {"back_face_culling", ToString(o.renderer.back_face_culling)},
          {"outside_margin_fraction", o.renderer.outside_margin_fraction}};
}

nlohmann::json ToJson(const SessionCheckOptions& o) {
  return {{"masks", o.masks_dir.empty() ? nlohmann::json() : nlohmann::json(fs::absolute(o.masks_dir).string())},
          {"mask_values", o.mask_values == MaskValues::kObjectId ? "object" : "instance"},
          {"crops", o.crops == CropBackend::kRenderer ? "renderer" : "surface"},
          {"track", o.track},
          {"frame_stride", o.frame_stride},
          {"frame_begin", o.frame_begin},
          {"frame_end", o.frame_end},
          {"skip_objects", o.skip_objects},
          {"seed", o.validate.check_seed == AcquisitionSeed::kLabel ? "label" : "view-sphere"}};
}

LabelOptions LabelOptionsFromJson(const nlohmann::json& json, const std::string& where) {
  const JsonFields f(json, where + " options");
  LabelOptions o;
  o.cameras = f.Strings("cameras");
  o.frame_begin = f.Integer("frame_begin"), o.frame_end = f.Integer("frame_end");
  const JsonFields out(f["output"], where + " options.output");
  o.output.write_depth = out.Bool("write_depth");
  o.output.depth_compression = DepthCompressionFromString(out.String("depth_compression"));
  o.output.write_masks = out.Bool("write_masks");
  o.output.write_bop_masks = out.Bool("write_bop_masks");
  o.output.write_overlay = out.Bool("write_overlay");
  o.chain.interpolation.max_gap_ns = f.Integer("max_gap_ns");
  o.chain.speed_half_window_ns = f.Integer("speed_half_window_ns");
  o.chain.fast_motion_m_per_s = f.Number("fast_motion_m_per_s");
  o.chain.fast_motion_deg_per_s = f.Number("fast_motion_deg_per_s");
  const JsonFields vis(f["visibility"], where + " options.visibility");
  // Runs written before the rule was recorded used BOP's (the only rule then): they are stale under another.
  o.visibility.rule = vis.Has("rule") ? ParseVisibilityRule(vis.String("rule"), where + " options.visibility.rule")
                                      : VisibilityRule::kBop19;
  // Runs written before the colour test on depth holes existed were made without it.
  o.visibility.hole_colour = vis.Has("hole_colour") && vis.Bool("hole_colour");
  o.visibility.delta_base_m = vis.Number("delta_base_m");
  o.visibility.noise_sigmas = vis.Number("noise_sigmas");
  o.visibility.noise_coeff_per_m = vis.Number("noise_coeff_per_m");
  o.renderer.back_face_culling = BackFaceCullingFromString(f.String("back_face_culling"));
  o.renderer.outside_margin_fraction = f.Number("outside_margin_fraction");
  return o;
}

SessionCheckOptions SessionCheckOptionsFromJson(const nlohmann::json& json, const std::string& where) {
  const JsonFields f(json, where + " options");
  SessionCheckOptions o;
  if (!f["masks"].is_null()) o.masks_dir = f.String("masks");
  const std::string values = f.String("mask_values"), crops = f.String("crops"), seed = f.String("seed");
  if (values != "object" && values != "instance") throw InputError(where, "options.mask_values: '" + values + "' is neither object nor instance");
  if (crops != "renderer" && crops != "surface") throw InputError(where, "options.crops: '" + crops + "' is neither renderer nor surface");
  if (seed != "label" && seed != "view-sphere") throw InputError(where, "options.seed: '" + seed + "' is neither label nor view-sphere");
  o.mask_values = values == "object" ? MaskValues::kObjectId : MaskValues::kInstanceId;
  o.crops = crops == "renderer" ? CropBackend::kRenderer : CropBackend::kSurface;
  o.validate.check_seed = seed == "label" ? AcquisitionSeed::kLabel : AcquisitionSeed::kViewSphere;
  o.track = f.Bool("track");
  o.frame_stride = static_cast<int>(f.Integer("frame_stride"));
  o.frame_begin = f.Integer("frame_begin"), o.frame_end = f.Integer("frame_end");
  for (const nlohmann::json& id : f["skip_objects"]) {
    if (!id.is_number_integer()) throw InputError(where, "options.skip_objects: every entry must be an object id");
    o.skip_objects.push_back(id.get<int>());
  }
  return o;
}

nlohmann::json ObjectsInSession(const ObjectLibrary& library, const SessionManifest& manifest) {
  std::set<std::string> bodies;
  for (const TrackerStreamInfo& tracker : manifest.trackers) bodies.insert(tracker.bodies.begin(), tracker.bodies.end());
  nlohmann::json digests = nlohmann::json::object();
  for (const LibraryObject& object : library.objects) {
    const bool seen = std::any_of(object.mounts.begin(), object.mounts.end(),
                                  [&](const BodyMount& m) { return bodies.count(m.body) > 0; });
    if (!seen) continue;
    ObjectLibrary entry;
    entry.objects.push_back(object);
    entry.objects.back().mesh.clear();  // the mesh is the input "mesh:<name>": its bytes count, not its path
    digests[object.name] = HashBytesXxh3(EmitObjectLibrary(entry));
  }
  return digests;
}

nlohmann::json RecordedOptions(nlohmann::json options, const RunRecord& record) {
  if (!record.objects_in_session.is_null()) options["objects_in_session"] = record.objects_in_session;
  return options;
}

void WriteProvenance(const fs::path& dir, const std::string& kind, const std::vector<std::string>& command,
                     const nlohmann::json& options, const std::vector<InputSpec>& inputs, const nlohmann::json& shard) {
  HashCache cache;
  RunProvenance run = NewProvenance(kind, command, options);
  run.inputs = FingerprintInputs(inputs, cache);
  run.shard = shard;
  WriteRunJson(dir, run);
}

}  // namespace mocap::pipeline
