#pragma once
// What the 3MF reader and writer share about lib3mf 1.x's C API (private to the library: it pulls in
// lib3mf's headers).

#include <Model/COM/NMR_DLLInterfaces.h>
#include <fmt/format.h>

#include <memory>
#include <string>

namespace poreshell {

// lib3mf 1.x hands out reference-counted handles that must each be released.
struct Lib3mfRelease {
  void operator()(NMR::PLib3MFBase* handle) const { NMR::lib3mf_release(handle); }
};
using Lib3mfHandle = std::unique_ptr<NMR::PLib3MFBase, Lib3mfRelease>;

// lib3mf's own message for a failed call on `handle`, or the bare error code.
inline std::string lib3mf_error_text(LIB3MFRESULT result, NMR::PLib3MFBase* handle) {
  DWORD code = 0;
  LPCSTR text = nullptr;
  if (handle != nullptr && NMR::lib3mf_getlasterror(handle, &code, &text) == LIB3MF_OK && text != nullptr)
    return text;
  return fmt::format("lib3mf error {:#x}", static_cast<unsigned>(result));
}

}  // namespace poreshell
