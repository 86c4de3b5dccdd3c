// Linked into every test (and the program in sanitizer builds): lib3mf 1.8.1 leaks a few hundred bytes
// of libzip state per 3MF file it reads (a ten-line program that only opens and releases a reader shows
// it too). Tell LeakSanitizer, in sanitizer builds; elsewhere nothing calls these. Its list of the
// suppressions used stays off stderr, where the program's one error line must stand alone.
extern "C" const char* __lsan_default_suppressions();
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libzip.so\n";
}
extern "C" const char* __lsan_default_options();
extern "C" const char* __lsan_default_options() {
  return "print_suppressions=0";
}
