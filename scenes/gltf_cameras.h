// The cameras of a glTF file's default scene, for the `:camera=N|name` scene parameter (load_scene). Declared
// apart from scene.h because only load_scene needs it; implemented by the glTF loader (gltf_loader.cpp).
#pragma once

#include <string>
#include <vector>

#include "scenes/scene.h"

namespace raycoh {

// One camera node, in the order the loader's traversal meets them (the first usable perspective one, else the
// first orthographic one, is the default view). name: the node's name, else the camera's, else "camera<N>".
struct FileCamera {
  std::string name;
  Camera camera;
  std::string unusable;  // empty when usable; else why not (e.g. "its transform or field of view is degenerate")
};

// Parses `path` again (glTF files only) and lists its cameras; throws raycoh::Error naming the file on failure.
std::vector<FileCamera> gltf_cameras(const std::string& path);

}  // namespace raycoh
