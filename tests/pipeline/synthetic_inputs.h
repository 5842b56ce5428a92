#pragma once
// A small labelling input built in a test: a session of the synthetic rig (tests/labeller) with
// measured depth, a 12 cm box on the object body, and its objects.yaml and rig.yaml written by the
// pipeline's writers.
#include <filesystem>
#include <fstream>
#include <string>

#include "pipeline/object_library.h"
#include "pipeline/rig.h"
#include "tests/labeller/labeller_test_util.h"

namespace mocap::testing {

/// A 12 cm box centred on the mesh origin, as an OBJ file (closed, outward faces).
inline void WriteBoxObj(const std::filesystem::path& path) {
  std::ofstream out(path);
  for (int i = 0; i < 8; ++i) out << "v " << ((i & 1) ? 0.06 : -0.06) << ' ' << ((i & 2) ? 0.06 : -0.06) << ' ' << ((i & 4) ? 0.06 : -0.06) << '\n';
  out << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
}

/// A session of `frames` frames of the synthetic rig with measured depth, its objects.yaml and rig.yaml.
struct Inputs {
  std::filesystem::path dir, session, objects, rig;
};
inline Inputs MakeInputs(const std::string& name, int frames) {
  Inputs in;
  in.dir = FreshDir(name);
  in.session = in.dir / "S", in.objects = in.dir / "objects.yaml", in.rig = in.dir / "rig.yaml";
  const SyntheticRig rig;
  const cv::Mat depth(TestCamera().height, TestCamera().width, CV_16UC1, cv::Scalar(790));
  rig.WriteSession(in.session, frames, -1, -1, depth);
  WriteBoxObj(in.dir / "box.obj");
  pipeline::ObjectLibrary library;
  pipeline::LibraryObject box;
  box.id = 3, box.name = "box", box.object_class = "box", box.mesh = "box.obj", box.mesh_path = in.dir / "box.obj";
  box.mounts.push_back({"objbody", rig.T_objbody_mesh});
  library.objects.push_back(box);
  pipeline::WriteObjectLibrary(library, in.objects);
  pipeline::Rig r;
  r.name = "test";
  r.tracker_latency_ns = 3'000'000;
  r.cameras.push_back({"cam", TestCamera(), "cambody", rig.T_cambody_camera, std::nullopt});
  pipeline::WriteRig(r, in.rig);
  return in;
}

}  // namespace mocap::testing
