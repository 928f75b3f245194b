// The one translation unit that compiles tinygltf's implementation (STYLE.md, "Build"). Debian's
// libtinygltf-dev also ships it as a shared library; orbis::scene does not link that, so the
// configuration in TinyGltf.h is the only one in play.
#define TINYGLTF_IMPLEMENTATION
#include "TinyGltf.h"
