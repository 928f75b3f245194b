#pragma once

// tinygltf as orbis::scene uses it (private: no public header names it). Every translation unit that
// includes tiny_gltf.h goes through here so that they all see the same configuration:
// * no stb_image inside tinygltf: GltfModel keeps images encoded and decodes them on upload,
// * no image writing (Orbis never writes glTF),
// * nlohmann::json, the one Orbis already uses, from its installed header.
// TinyGltf.cpp compiles the implementation once.

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>
