# Finds mereo's dependencies (all from Debian 12 packages; see scripts/setup-debian.sh).
# MEREO_PUBLIC_LIBS: what public headers need (Eigen only).
# MEREO_PRIVATE_LIBS: what the .cpp files need (PCL for PCD files, OpenCV, oneTBB, JSON, YAML).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(TBB REQUIRED)
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs rgbd ximgproc)
find_package(nlohmann_json 3 REQUIRED)
find_package(yaml-cpp REQUIRED)  # graph files and object models (errors name the line)
# PCL's config pulls in VTK, which wants MPI's C target.
find_package(MPI COMPONENTS C QUIET)
find_package(PCL 1.12 REQUIRED COMPONENTS common io)

set(MEREO_PUBLIC_LIBS Eigen3::Eigen)
# Only the PCL libraries we call (PCL_LIBRARIES would add all of VTK to the link line).
set(MEREO_PRIVATE_LIBS TBB::tbb ${OpenCV_LIBS} nlohmann_json::nlohmann_json yaml-cpp pcl_io pcl_common)
set(MEREO_PRIVATE_INCLUDES ${PCL_INCLUDE_DIRS} ${OpenCV_INCLUDE_DIRS})
include_directories(SYSTEM ${MEREO_PRIVATE_INCLUDES})
