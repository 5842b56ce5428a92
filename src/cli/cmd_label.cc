// mocaplabel label S [--rig R] [--objects O] [--out DIR]: masks, rendered depth, poses and flags for
// every frame (src/label/labeller.h).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "cli/parse_args.h"
#include "cli/commands.h"
#include "cli/progress_flag.h"
#include "core/check.h"
#include "pipeline/label_stage.h"

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;

void PrintHuman(const LabelSummary& s, const fs::path& out) {
  std::printf("labelled %lld frames (%lld skipped: image files missing), %lld object records, %lld with a pose\n",
              static_cast<long long>(s.frames), static_cast<long long>(s.frames_skipped),
              static_cast<long long>(s.records), static_cast<long long>(s.records_with_pose));
  std::printf("flagged frames: %lld", static_cast<long long>(s.frames_flagged));
  for (const auto& [flag, n] : s.flag_counts) std::printf("  %s=%lld", flag.c_str(), static_cast<long long>(n));
  const double rate = s.frames_seconds > 0 ? static_cast<double>(s.frames) / s.frames_seconds : 0.0;
  std::printf("\n%.2f s: set-up %.2f s, then %.1f frames/s (render %.2f s summed over threads); output in %s\n",
              s.seconds, s.setup_seconds, rate, s.render_seconds, out.string().c_str());
}

}  // namespace

int RunLabel(int argc, char** argv) {
  CLI::App app{"Label every frame of a session: masks, rendered depth, poses and flags", "mocaplabel label"};
  std::string session_dir, rig_file, objects_file, out_dir, platform = "auto";
  pipeline::LabelRunRequest request;
  LabelOptions& options = request.label;
  double max_gap_ms = 50.0;
  bool json = false;
  app.add_option("session", session_dir, "session folder")->required();
  app.add_option("--rig", rig_file, "rig calibration YAML (default: the calibration recorded in the session)");
  app.add_option("--objects", objects_file, "object library YAML (default: the session's objects.yaml)");
  app.add_option("--out", out_dir, "output folder (default: SESSION/labels)");
  app.add_option("--camera", options.cameras, "camera to label (repeatable; default: all)");
  app.add_option("--threads", options.threads, "worker threads, each with its own EGL context (0: one per core)")
      ->check(CLI::Range(0, 256));
  app.add_option("--max-gap-ms", max_gap_ms, "longest tracker gap bridged by interpolation")
      ->check(CLI::Range(0.001, 60'000.0));
  app.add_option("--outside-margin", options.renderer.outside_margin_fraction,
                 "render canvas margin per side, as a fraction of the image, so that amodal boxes and pixel "
                 "counts include what lies outside the image (1 = BOP's 3x canvas)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--platform", platform, "EGL platform: auto, surfaceless or device");
  app.add_flag("--overlay", options.output.write_overlay, "also write label colours over the RGB image");
  bool no_masks = false, no_depth = false;
  std::string depth_compression = "rle", culling = "auto";
  app.add_flag("--no-masks", no_masks, "skip the per-object packed mask PNGs");
  app.add_flag("--bop-masks", options.output.write_bop_masks,
               "also write three full-size 0/255 mask PNGs per object (mask/, mask_visib/, mask_visib_depth/)");
  app.add_flag("--no-depth", no_depth, "skip the rendered depth (OpenEXR)");
  app.add_option("--depth-compression", depth_compression, "OpenEXR codec of the rendered depth: none, rle, zips, zip, piz");
  app.add_option("--cull-back-faces", culling,
                 "auto (meshes found closed and outward-wound), always or never; objects.yaml cull_back_faces wins");
  std::string visibility = std::string(ToString(options.visibility.rule));
  app.add_option("--visibility", visibility,
                 "visible-mask rule against the measured depth: combined (model z-buffer, measured depth, depth holes "
                 "judged from their surroundings) or bop19 (BOP's mask_visib exactly, for datasets compared with BOP's tools)")
      ->check(CLI::IsMember({"combined", "bop19"}));
  bool no_hole_colour = false;
  app.add_flag("--no-hole-colour", no_hole_colour,
               "combined rule: leave out the colour test on depth holes (a hole pixel whose colour the object has "
               "neither in its measured pixels nor on its mesh is hidden; docs/labels.md)");
  app.add_flag("--stop-on-bad-image", options.stop_on_unreadable_image,
               "stop at a depth or colour file that cannot be decoded (default: label the frame without it and "
               "flag its records unreadable_depth / unreadable_color)");
  app.add_flag("--json", json, "print one JSON summary on stdout");
  ProgressFlags progress_flags;
  AddProgressFlags(app, progress_flags);
  MOCAP_PARSE(app, argc, argv);
  const std::unique_ptr<ProgressSink> progress = ApplyProgressFlags(progress_flags);
  request.progress = progress.get();

  request.session_dir = session_dir;
  request.rig_file = rig_file;
  request.objects_file = objects_file;
  request.out_dir = out_dir.empty() ? fs::path(session_dir) / "labels" : fs::path(out_dir);
  request.command = CommandLine(argc, argv);
  options.output.write_masks = !no_masks;
  options.output.write_depth = !no_depth;
  options.output.depth_compression = DepthCompressionFromString(depth_compression);
  options.chain.interpolation.max_gap_ns = static_cast<int64_t>(max_gap_ms * 1e6);
  options.context.platform = EglPlatformFromString(platform);
  options.renderer.back_face_culling = BackFaceCullingFromString(culling);
  options.visibility.rule = ParseVisibilityRule(visibility, "--visibility");
  if (no_hole_colour) options.visibility.hole_colour = false;
  // Every worker owns a context and keeps a core busy; llvmpipe's own rasteriser threads (one per core by
  // default) then only add hand-over cost: 36 -> 29-34 ms CPU per frame with 2 workers (bench/RESULTS.md,
  // bench_label). Mesa reads the variable once, at the first EGL display, which is still to come here.
  if (options.threads != 1 && std::getenv("LP_NUM_THREADS") == nullptr) setenv("LP_NUM_THREADS", "0", 0);
  const pipeline::LabelRunResult result = pipeline::RunLabel(request);
  const LabelSummary& summary = result.summary;
  if (json) {
    const nlohmann::json j = {{"frames", summary.frames},          {"frames_skipped", summary.frames_skipped},
                              {"records", summary.records},        {"records_with_pose", summary.records_with_pose},
                              {"frames_flagged", summary.frames_flagged}, {"flag_counts", summary.flag_counts},
                              {"seconds", summary.seconds},        {"setup_seconds", summary.setup_seconds},
                              {"frames_seconds", summary.frames_seconds}, {"render_seconds", summary.render_seconds},
                              {"complete", true},                  {"out", result.out_dir.string()}};
    std::printf("%s\n", j.dump().c_str());
  } else {
    PrintHuman(summary, result.out_dir);
  }
  return 0;
}

}  // namespace mocap::cli
