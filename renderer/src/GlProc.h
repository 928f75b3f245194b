#pragma once

// How a backend hands out GL entry points. Kept apart from GlApi.h so that backends whose headers
// bring their own GL declarations (OSMesa includes GL/gl.h) need not see glcorearb.h. Private.

namespace orbis::renderer::detail {

using GlProc = void (*)();
using GetProcAddressFunction = GlProc (*)(const char* name);

} // namespace orbis::renderer::detail
