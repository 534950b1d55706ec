# cmake -DSTAGE=<dir> -DMESHLAB_LIBDIR=<debian meshlab lib dir> -DBINARIES=<paths> -P stage.cmake
# Builds the staging prefix: STAGE/bin/<copies of the real binaries> and
# STAGE/lib/x86_64-linux-gnu/meshlab/{libmeshlab-common.so, plugins/*} as symlinks to Debian's
# files; the thermodec plugin is already built into STAGE/.../plugins. The binaries are copied,
# not linked, because MeshLab resolves its plugin folder from the real path of the executable.
set(_lib "${STAGE}/lib/x86_64-linux-gnu/meshlab")
file(MAKE_DIRECTORY "${STAGE}/bin" "${_lib}/plugins")
foreach(_bin ${BINARIES})
  if(_bin AND EXISTS "${_bin}")
    get_filename_component(_name "${_bin}" NAME)
    file(COPY "${_bin}" DESTINATION "${STAGE}/bin" FILE_PERMISSIONS
         OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
  endif()
endforeach()
file(CREATE_LINK "${MESHLAB_LIBDIR}/libmeshlab-common.so" "${_lib}/libmeshlab-common.so" SYMBOLIC)
file(GLOB _stock RELATIVE "${MESHLAB_LIBDIR}/plugins" "${MESHLAB_LIBDIR}/plugins/*.so")
foreach(_p ${_stock})
  # A thermodec plugin installed system-wide by an earlier `cmake --install` would be loaded
  # twice (same filter names): the staged build wins.
  if(NOT _p STREQUAL "libfilter_thermodec.so")
    file(CREATE_LINK "${MESHLAB_LIBDIR}/plugins/${_p}" "${_lib}/plugins/${_p}" SYMBOLIC)
  endif()
endforeach()
