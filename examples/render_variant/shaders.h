#pragma once
// The generated library (aovar generate --emit cpp --targets vulkan), under the one name the rest of the program
// uses. Its header's file name and namespace are the same (--namespace, default aovar_shaders); CMakeLists.txt
// passes both, so a library generated with another --namespace needs only -DRENDER_VARIANT_NAMESPACE.
#include RENDER_VARIANT_HEADER

namespace shaders = RENDER_VARIANT_NAMESPACE;
