# Dear ImGui's two halves, kept apart: the OpenGL3 renderer half alone draws the headless
# charts of `apiclab figures` (app/figures), and the GLFW platform half adds the window of
# the viewer (app/gui, app/cmd_gui.cpp, under APICLAB_BUILD_GUI). Debian's libimgui-dev ships
# the backends as sources only: they are compiled from its examples folder at build time.
if(NOT TARGET apiclab_render)
  if(APICLAB_BUILD_GUI)
    message(STATUS "GUI and figures not built: they need the renderer (render/)")
  endif()
  return()
endif()

find_package(PkgConfig REQUIRED)
if(APICLAB_BUILD_GUI)
  pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)
else()
  pkg_check_modules(IMGUI IMPORTED_TARGET imgui)
  if(NOT IMGUI_FOUND)
    message(STATUS "figures not built: it needs Dear ImGui (apt-get install libimgui-dev)")
    return()
  endif()
endif()
set(APICLAB_IMGUI_BACKENDS "/usr/share/doc/libimgui-dev/examples/backends" CACHE PATH
    "Directory holding imgui_impl_glfw.cpp and imgui_impl_opengl3.cpp")
set(_imgui_backends imgui_impl_opengl3.cpp)
if(APICLAB_BUILD_GUI)
  list(APPEND _imgui_backends imgui_impl_glfw.cpp)
endif()
foreach(_backend ${_imgui_backends})
  if(NOT EXISTS "${APICLAB_IMGUI_BACKENDS}/${_backend}")
    message(FATAL_ERROR "needs ${APICLAB_IMGUI_BACKENDS}/${_backend}: apt-get install libimgui-dev "
                        "(or -DAPICLAB_BUILD_GUI=OFF)")
  endif()
endforeach()

# The renderer half: no window system, GL loaded through libglvnd.
add_library(apiclab_imgui_opengl3 STATIC "${APICLAB_IMGUI_BACKENDS}/imgui_impl_opengl3.cpp")
target_include_directories(apiclab_imgui_opengl3 SYSTEM PUBLIC /usr/include/imgui/backends)
target_link_libraries(apiclab_imgui_opengl3 PUBLIC PkgConfig::IMGUI ${CMAKE_DL_LIBS})
target_compile_options(apiclab_imgui_opengl3 PRIVATE -w)

# Charts drawn offscreen: the plot widget (app/gui/plot.cpp, ImGui only) on a ChartCanvas.
add_library(apiclab_charts STATIC gui/plot.cpp figures/chart_canvas.cpp)
target_include_directories(apiclab_charts PUBLIC "${CMAKE_CURRENT_SOURCE_DIR}/..")
target_link_libraries(apiclab_charts PUBLIC apiclab_imgui_opengl3 apiclab_render)

# `apiclab figures`: the paper's charts and frames.
target_sources(apiclab PRIVATE cmd_figures.cpp figures/catalogue.cpp figures/time_figure.cpp
                               figures/roundtrip_figure.cpp figures/ringing_frames.cpp
                               figures/chart_style.cpp figures/scheme_energy_figure.cpp)
target_sources(apiclab PRIVATE sweep/charts.cpp)  # `apiclab sweep`'s charts
target_link_libraries(apiclab PRIVATE apiclab_charts)
target_compile_definitions(apiclab PRIVATE APICLAB_HAVE_FIGURES=1)

if(NOT APICLAB_BUILD_GUI)
  return()
endif()
# The viewer: the platform half and GLFW on top.
find_package(glfw3 3.3 REQUIRED)
add_library(apiclab_imgui_glfw STATIC "${APICLAB_IMGUI_BACKENDS}/imgui_impl_glfw.cpp")
target_include_directories(apiclab_imgui_glfw SYSTEM PUBLIC /usr/include/imgui/backends)
target_link_libraries(apiclab_imgui_glfw PUBLIC PkgConfig::IMGUI glfw)
target_compile_options(apiclab_imgui_glfw PRIVATE -w)

target_sources(apiclab PRIVATE cmd_gui.cpp gui/viewer.cpp gui/controls.cpp gui/scene_view.cpp
                               gui/plots_panel.cpp gui/sweep_panel.cpp gui/pane_checkpoint.cpp)
# Its file-local colours share names with controls.cpp's: compiled apart in a unity build.
set_source_files_properties(gui/sweep_panel.cpp PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
target_link_libraries(apiclab PRIVATE apiclab_imgui_glfw)
target_compile_definitions(apiclab PRIVATE APICLAB_HAVE_GUI=1)
