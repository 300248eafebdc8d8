# `cpack -G DEB` in the build folder: contact2d_<version>_<arch>.deb, everything under /usr.
# The package is for building against contact2d, so it depends on the -dev packages the CMake
# package config finds; dpkg-shlibdeps adds the shared libraries the program loads.
set(CPACK_PACKAGE_NAME contact2d)
set(CPACK_PACKAGE_CONTACT "contact2d developers")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "2D finite-element contact solver: library, headers, CLI")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
string(JOIN ", " CPACK_DEBIAN_PACKAGE_DEPENDS "libeigen3-dev (>= 3.4)" "libtomlplusplus-dev (>= 3)"
     libsuitesparse-dev coinor-libipopt-dev "libsundials-dev (>= 6.4)" libgmsh-dev pkg-config)
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "gnuplot-nox")
include(CPack)
