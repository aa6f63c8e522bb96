// Linked into every executable of a sanitized build (AOVAR_SANITIZE, top CMakeLists.txt): dlclose does
// nothing, so the Mesa drivers that the Vulkan loader and OSMesa unload stay mapped until exit and
// LeakSanitizer can still name them in its stacks. Without it their process-lifetime allocations show as
// "<unknown module>", which no suppression can match. The executable exports it (--export-dynamic-symbol)
// and comes first in the global lookup scope, so the drivers' and the loader's calls bind to it, before
// ASan's interceptor and libc.
extern "C" int dlclose(void* handle) {
  (void)handle;
  return 0;
}
