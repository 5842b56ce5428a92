#include "pipeline/run_provenance.h"

#include "label/depth_exr.h"
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
          {"visibility", {{"delta_base_m", o.visibility.delta_base_m}, {"noise_sigmas", o.visibility.noise_sigmas},
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

void WriteProvenance(const fs::path& dir, const std::string& kind, const std::vector<std::string>& command,
                     const nlohmann::json& options, const std::vector<InputSpec>& inputs, const nlohmann::json& shard) {
  HashCache cache;
  RunProvenance run = NewProvenance(kind, command, options);
  run.inputs = FingerprintInputs(inputs, cache);
  run.shard = shard;
  WriteRunJson(dir, run);
}

}  // namespace mocap::pipeline
