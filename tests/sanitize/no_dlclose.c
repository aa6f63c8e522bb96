/* Preloaded by scripts/sanitize: dlclose does nothing, so the Mesa drivers that the Vulkan loader and
 * OSMesa unload stay mapped until exit and LeakSanitizer can still name them in its stacks. Without it
 * their process-lifetime allocations show as "<unknown module>", which no suppression can match. */
int dlclose(void *handle) {
  (void)handle;
  return 0;
}
