// The shared library has no code of its own: it is the core's objects with only the public API
// (include/poreshell/, marked PORESHELL_API) visible. CMake needs one source to make it.
