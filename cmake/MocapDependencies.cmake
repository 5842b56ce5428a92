# All third-party packages come from Debian's archive (scripts/install-deps.sh installs them).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(Threads REQUIRED)
find_package(OpenMP REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc imgcodecs calib3d aruco)
# src/calibrate: the camera-mount refinement (Debian libceres-dev)
find_package(Ceres 2 REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
# The one logging sink (core/log.h); Debian's build uses Debian's libfmt (SPDLOG_FMT_EXTERNAL).
find_package(spdlog REQUIRED)
find_package(PkgConfig REQUIRED)

if(BUILD_TESTING)
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()
if(BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
  # The validator benchmarks' baselines (PCL's and Open3D's ICP); only bench/ links them.
  find_package(PCL 1.10 QUIET COMPONENTS common io registration kdtree search features filters)
  find_package(Open3D QUIET)
endif()
find_package(ZLIB REQUIRED)
# Whole-buffer inflate and CRC-32/Adler-32 (SIMD) for the depth PNG decoder and the label encoders.
pkg_check_modules(LIBDEFLATE REQUIRED IMPORTED_TARGET libdeflate)
# Content hashes of run inputs (provenance run.json): XXH3-128, streaming API (xxHash >= 0.8).
pkg_check_modules(LIBXXHASH REQUIRED IMPORTED_TARGET libxxhash>=0.8)
find_package(OpenEXR 3 REQUIRED CONFIG)
# Headless rendering: EGL + desktop OpenGL through glvnd (libEGL, libOpenGL), meshes through assimp.
set(OpenGL_GL_PREFERENCE GLVND)
find_package(OpenGL REQUIRED COMPONENTS EGL OpenGL)
find_package(assimp REQUIRED)
