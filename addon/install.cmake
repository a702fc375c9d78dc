# Blender add-on install and zip.  Included from the top-level CMakeLists.txt.
#
#   cmake --install build                       # installs everything, the add-on included
#   cmake --install build --component blender_addon   # only the add-on
#   cmake --build build --target addon_zip      # build/rendezvous-addon.zip for
#                                               # Edit > Preferences > Add-ons > Install
#
# The add-on is ONE folder, `rendezvous/`: the contents of addon/, shaders_map/ as a
# sub-package, and librendezvous.so beside __init__.py.  Destination, decided at INSTALL
# time: RDV_ADDON_INSTALL_DIR if set, else $BLENDER_USER_SCRIPTS/addons/rendezvous when
# that variable is set, else ~/.config/blender/<RDV_BLENDER_VERSION>/scripts/addons/rendezvous.

set(RDV_ADDON_INSTALL_DIR "" CACHE PATH
    "Install the Blender add-on folder here (empty: $BLENDER_USER_SCRIPTS/addons/rendezvous or the user add-on folder)")
set(RDV_BLENDER_VERSION "3.4" CACHE STRING "Blender version of the default user add-on folder")

get_filename_component(_rdv_root "${CMAKE_CURRENT_LIST_DIR}" DIRECTORY)
set(_rdv_addon_src "${_rdv_root}/addon")
set(_rdv_shaders_src "${_rdv_root}/shaders_map")

# install() destinations are fixed at configure time; the escaped \${...} below are
# expanded when cmake_install.cmake runs, after this CODE computed them.  CMake prefixes a
# relative DESTINATION with CMAKE_INSTALL_PREFIX, so hand it the path relative to that.
install(CODE "
  set(_dest \"${RDV_ADDON_INSTALL_DIR}\")
  if(_dest STREQUAL \"\")
    if(DEFINED ENV{BLENDER_USER_SCRIPTS} AND NOT \"\$ENV{BLENDER_USER_SCRIPTS}\" STREQUAL \"\")
      set(_dest \"\$ENV{BLENDER_USER_SCRIPTS}/addons/rendezvous\")
    else()
      set(_dest \"\$ENV{HOME}/.config/blender/${RDV_BLENDER_VERSION}/scripts/addons/rendezvous\")
    endif()
  endif()
  get_filename_component(_dest \"\${_dest}\" ABSOLUTE)
  file(RELATIVE_PATH RDV_ADDON_DEST_REL \"\${CMAKE_INSTALL_PREFIX}\" \"\${_dest}\")
  if(RDV_ADDON_DEST_REL STREQUAL \"\")
    set(RDV_ADDON_DEST_REL .)
  endif()
  message(STATUS \"Blender add-on -> \${_dest}\")
" COMPONENT blender_addon)

install(DIRECTORY "${_rdv_addon_src}/" DESTINATION "\${RDV_ADDON_DEST_REL}" COMPONENT blender_addon
        PATTERN "__pycache__" EXCLUDE PATTERN "*.pyc" EXCLUDE PATTERN ".gitignore" EXCLUDE
        PATTERN "install.cmake" EXCLUDE PATTERN "make_zip.cmake" EXCLUDE)
install(DIRECTORY "${_rdv_shaders_src}" DESTINATION "\${RDV_ADDON_DEST_REL}" COMPONENT blender_addon
        PATTERN "__pycache__" EXCLUDE PATTERN "*.pyc" EXCLUDE PATTERN ".gitignore" EXCLUDE)
install(TARGETS rendezvous LIBRARY DESTINATION "\${RDV_ADDON_DEST_REL}" COMPONENT blender_addon)

# A zip with the same layout, for Edit > Preferences > Add-ons > Install.
add_custom_target(addon_zip
  COMMAND "${CMAKE_COMMAND}" -DSTAGE=${CMAKE_BINARY_DIR}/addon_stage
          -DADDON_SRC=${_rdv_addon_src} -DSHADERS_SRC=${_rdv_shaders_src}
          -DLIBRARY=$<TARGET_FILE:rendezvous> -DZIP=${CMAKE_BINARY_DIR}/rendezvous-addon.zip
          -P "${_rdv_addon_src}/make_zip.cmake"
  DEPENDS rendezvous
  COMMENT "Packing the Blender add-on into ${CMAKE_BINARY_DIR}/rendezvous-addon.zip"
  VERBATIM)
