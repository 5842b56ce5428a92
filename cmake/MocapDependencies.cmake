# All third-party packages come from Debian's archive (scripts/install-deps.sh installs them).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(Threads REQUIRED)
find_package(OpenMP REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc imgcodecs calib3d)
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
find_package(PkgConfig REQUIRED)

if(BUILD_TESTING)
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()
if(BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
  # The validator benchmark's baseline (pcl::IterativeClosestPoint); only bench/ links it.
  find_package(PCL 1.10 QUIET COMPONENTS common io registration kdtree search)
endif()
