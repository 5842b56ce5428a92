#pragma once
// `mocaplabel sim record` and the demo's first stages: a simulated session written with its truth, plus
// the rig.yaml and objects.yaml of the calibration handed to the labeller (written by this module's
// writers, rig.h and object_library.h, before the session is closed); and the capture stage, which plays
// that session through the capture daemon in real time (capture/daemon/rerecord.h).
#include <filesystem>

#include "pipeline/object_library.h"
#include "pipeline/rig.h"
#include "pipeline/stage.h"
#include "sim/record/sim_recorder.h"

namespace mocap::pipeline {

struct SimRecordResult {
  sim::RecordResult record;
  std::filesystem::path rig_file, objects_file;  ///< S/rig.yaml, S/objects.yaml
};

/// Simulates `scenario` with the objects of `library` (the built-in library when null: its meshes are
/// generated into S/meshes). Throws InputError like sim::RecordSimulation.
SimRecordResult RecordSimulatedSession(const sim::Scenario& scenario, const ObjectLibrary* library,
                                       const sim::RecordOptions& options);

/// The given calibration of a recording as a rig (camera `camera` on `camera_body`).
Rig RigOfCalibration(const sim::RigCalibration& calibration, const std::string& rig_name, const std::string& camera,
                     const std::string& camera_body);

/// The object library of a recording made with the built-in objects (meshes in record.library_dir).
ObjectLibrary BuiltInLibraryOf(const sim::RecordResult& record);

/// rig.yaml and objects.yaml of `calibration` (true, given or perturbed) for a recording of `library`'s
/// objects, written into `dir`: what the labeller reads. The record stage writes the given calibration's
/// into the session.
struct CalibrationFiles {
  std::filesystem::path rig, objects;
};
CalibrationFiles WriteCalibrationFiles(const sim::RecordResult& record, const ObjectLibrary& library,
                                       const sim::RigCalibration& calibration, const std::string& rig_name,
                                       const std::filesystem::path& dir);

/// writes `meshes/objects.yaml` for the built-in library whose meshes are in `mesh_dir`.
std::filesystem::path WriteBuiltInObjectLibrary(const std::filesystem::path& mesh_dir);

/// Records `scenario` into context.out_dir/simulated (sets session_dir, rig_file, objects_file,
/// truth_dir, camera, results["record"]).
Stage MakeRecordStage(const sim::Scenario& scenario);
/// Plays context.session_dir through the capture daemon into context.out_dir/session and makes that
/// the session later stages read (results["capture"]).
Stage MakeCaptureStage();

}  // namespace mocap::pipeline
