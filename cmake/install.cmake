# `cmake --install`: the tools in bin, relightd's systemd units in
# lib/systemd/system with ExecStart pointing at the installed relightd, the
# docs in share/doc/relight. Checked by the ctest InstallTree
# (scripts/check-install.sh: a DESTDIR install, its file list and
# `systemd-analyze verify` on the installed units).
include(GNUInstallDirs)

# Units go where Debian's systemd looks for packaged ones (relative to the
# prefix; /usr/local/lib/systemd/system is read too).
set(RELIGHT_SYSTEMD_UNITDIR "lib/systemd/system" CACHE STRING "where the systemd units are installed (under the prefix)")

foreach(tool relightd relight-bake relight-render relight-probe relight-lid relight-replay-hash relight-fixture-type)
  if(TARGET ${tool})  # a runtime-only build has no baker and no daemon
    install(TARGETS ${tool} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endforeach()

if(TARGET relightd)
  # The units in the tree name /usr/local/bin/relightd (they work as they are
  # when copied by hand); the installed ones name this install's relightd.
  file(GLOB units CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/runtime/daemon/systemd/*.service)
  foreach(unit ${units})
    get_filename_component(name ${unit} NAME)
    file(READ ${unit} text)
    string(REPLACE "/usr/local/bin/relightd" "${CMAKE_INSTALL_FULL_BINDIR}/relightd" text "${text}")
    # Written as is (no ${} or @@ substitution: the units use both signs).
    set(out ${CMAKE_BINARY_DIR}/systemd/${name})
    set(old "")
    if(EXISTS ${out})
      file(READ ${out} old)
    endif()
    if(NOT old STREQUAL text)
      file(WRITE ${out} "${text}")
    endif()
    install(FILES ${CMAKE_BINARY_DIR}/systemd/${name} DESTINATION ${RELIGHT_SYSTEMD_UNITDIR})
  endforeach()
endif()

file(GLOB docs ${PROJECT_SOURCE_DIR}/docs/*.md)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${docs} DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/figures DESTINATION ${CMAKE_INSTALL_DOCDIR})
