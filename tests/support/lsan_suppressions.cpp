// Linked into every test: lib3mf 1.8.1 leaks a few hundred bytes of libzip state per 3MF file it reads
// (a ten-line program that only opens and releases a reader shows it too). Tell LeakSanitizer, in
// sanitizer builds; elsewhere nothing calls this.
extern "C" const char* __lsan_default_suppressions();
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libzip.so\n";
}
