# `cmake --install build --prefix P`: the libraries core, constraints and nonlinear (static),
# and the run layer over them (app/run/run_scene.hpp: a whole run, its files and summary, as
# `contact2d run` does it; with the report and process layers it uses), their headers under
# P/include/contact2d/<module>/ (so `#include "core/model.hpp"` works as in this tree), the
# contact2d program, and the CMake package P/lib/cmake/contact2d that gives contact2d::core,
# contact2d::constraints, contact2d::nonlinear and contact2d::run to find_package(contact2d).
include(CMakePackageConfigHelpers)

# Installed under /usr by a package, libcore.a would be anybody's: the files carry the project.
foreach(_c2d_module core constraints nonlinear)
  set_target_properties(${_c2d_module} PROPERTIES OUTPUT_NAME contact2d_${_c2d_module})
endforeach()

set(C2D_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/contact2d")

install(TARGETS core constraints nonlinear app_process app_report app_run EXPORT contact2dTargets
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
        LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
        RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
install(TARGETS contact2d RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
# The program's code, loaded by bin/contact2d from here (app/cli/launcher.cpp).
install(TARGETS contact2d_cli LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}/contact2d")
foreach(_c2d_module core constraints nonlinear)
  install(DIRECTORY "${PROJECT_SOURCE_DIR}/${_c2d_module}/"
          DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/contact2d/${_c2d_module}"
          FILES_MATCHING PATTERN "*.hpp")
endforeach()

# The run layer's headers: app/*.hpp, app/report/ and app/run/ (not the command line's).
install(DIRECTORY "${PROJECT_SOURCE_DIR}/app/" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/contact2d/app"
        FILES_MATCHING PATTERN "*.hpp" PATTERN cli EXCLUDE PATTERN studies EXCLUDE)

install(EXPORT contact2dTargets NAMESPACE contact2d:: DESTINATION "${C2D_INSTALL_CMAKEDIR}")
configure_package_config_file(cmake/contact2dConfig.cmake.in
                              "${PROJECT_BINARY_DIR}/contact2dConfig.cmake"
                              INSTALL_DESTINATION "${C2D_INSTALL_CMAKEDIR}")
# 0.x: a new minor version may change the API.
write_basic_package_version_file("${PROJECT_BINARY_DIR}/contact2dConfigVersion.cmake"
                                 COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/contact2dConfig.cmake"
              "${PROJECT_BINARY_DIR}/contact2dConfigVersion.cmake"
              "${PROJECT_SOURCE_DIR}/cmake/contact2dThirdParty.cmake"
        DESTINATION "${C2D_INSTALL_CMAKEDIR}")
