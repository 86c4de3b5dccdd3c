#pragma once
// Symbols of the shared library that callers see; everything else in it is hidden.

#define PORESHELL_API __attribute__((visibility("default")))
