# The GLFW + Dear ImGui viewer (app/gui, app/cmd_gui.cpp), under APICLAB_BUILD_GUI.
# Debian's libimgui-dev ships the platform/renderer backends as sources only: they are
# compiled from /usr/share/doc/libimgui-dev/examples/backends at build time.
if(APICLAB_BUILD_GUI AND TARGET apiclab_render)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)
  find_package(glfw3 3.3 REQUIRED)
  set(APICLAB_IMGUI_BACKENDS "/usr/share/doc/libimgui-dev/examples/backends" CACHE PATH
      "Directory holding imgui_impl_glfw.cpp and imgui_impl_opengl3.cpp")
  foreach(_backend imgui_impl_glfw.cpp imgui_impl_opengl3.cpp)
    if(NOT EXISTS "${APICLAB_IMGUI_BACKENDS}/${_backend}")
      message(FATAL_ERROR "GUI needs ${APICLAB_IMGUI_BACKENDS}/${_backend}: apt-get install libimgui-dev "
                          "(or -DAPICLAB_BUILD_GUI=OFF)")
    endif()
  endforeach()
  add_library(apiclab_imgui_backends STATIC "${APICLAB_IMGUI_BACKENDS}/imgui_impl_glfw.cpp"
                                            "${APICLAB_IMGUI_BACKENDS}/imgui_impl_opengl3.cpp")
  target_include_directories(apiclab_imgui_backends SYSTEM PUBLIC /usr/include/imgui/backends)
  target_link_libraries(apiclab_imgui_backends PUBLIC PkgConfig::IMGUI glfw ${CMAKE_DL_LIBS})
  target_compile_options(apiclab_imgui_backends PRIVATE -w)

  # The worker alone (no window): the GUI tests drive it headless, TSAN included.
  add_library(apiclab_gui_worker STATIC gui/sim_worker.cpp)
  target_include_directories(apiclab_gui_worker PUBLIC "${CMAKE_CURRENT_SOURCE_DIR}/..")
  find_package(Threads REQUIRED)
  target_link_libraries(apiclab_gui_worker PUBLIC apiclab_sim Threads::Threads)

  target_sources(apiclab PRIVATE gui/viewer.cpp gui/controls.cpp gui/scene_view.cpp
                                 gui/plots_panel.cpp gui/plot.cpp)
  target_include_directories(apiclab PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}/..")
  target_link_libraries(apiclab PRIVATE apiclab_gui_worker apiclab_imgui_backends)
  target_compile_definitions(apiclab PRIVATE APICLAB_HAVE_GUI=1)
elseif(APICLAB_BUILD_GUI)
  message(STATUS "GUI not built: it needs the renderer (render/)")
endif()

# `apiclab figures` (app/cmd_figures.cpp): the paper's charts are drawn by the GUI's plot
# widget offscreen through ImGui's OpenGL3 backend, so the command comes with the GUI.
if(TARGET apiclab_imgui_backends AND EXISTS "${CMAKE_CURRENT_SOURCE_DIR}/cmd_figures.cpp")
  target_sources(apiclab PRIVATE figures/chart_canvas.cpp)
  target_compile_definitions(apiclab PRIVATE APICLAB_HAVE_FIGURES=1)
endif()
