# All dependencies come from Debian packages (launch_scripts/setup.sh installs them;
# GoogleTest and Google Benchmark only when the tests are built: setup.sh --tests).
find_package(PkgConfig REQUIRED)
pkg_check_modules(LCM REQUIRED IMPORTED_TARGET lcm)
pkg_check_modules(ARAVIS REQUIRED IMPORTED_TARGET aravis-0.8)
pkg_check_modules(GPIOD REQUIRED IMPORTED_TARGET libgpiod)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
# Every conversion between geodetic and local coordinates (common/geodetic.cc).
pkg_check_modules(GEOGRAPHICLIB REQUIRED IMPORTED_TARGET geographiclib)
find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc video calib3d imgcodecs features2d)
find_package(yaml-cpp REQUIRED)
find_package(Threads REQUIRED)
# JSON for the Foxglove topics and the MCAP export (nadir_log); the Foxglove
# WebSocket bridge also needs websocketpp on Boost.Asio (optional: without
# them nadir_foxglove is not built, e.g. in the demo's build).
find_package(nlohmann_json 3 REQUIRED)
find_package(websocketpp QUIET)
find_package(Boost 1.70 QUIET)
# GeoTIFF maps (tools/map: the simulated reference map and its reader) with
# GDAL (Debian libgdal-dev); optional: without it nadir_map is not built.
find_package(GDAL QUIET)
find_package(Java COMPONENTS Development)
find_program(LCM_GEN lcm-gen REQUIRED)
if(NADIR_BUILD_TESTS)
  find_package(GTest REQUIRED)
  find_package(benchmark REQUIRED)
endif()
