// A scratch folder for a unit test that writes files, removed with everything in it at the
// end of its scope.
#pragma once

#include <stdlib.h>

#include <filesystem>
#include <string>

struct ScratchDir {
  std::filesystem::path dir;
  explicit ScratchDir(const std::string& name) {
    std::string t = (std::filesystem::temp_directory_path() / ("cdpile-" + name + "-XXXXXX")).string();
    dir = mkdtemp(t.data());
  }
  ~ScratchDir() { std::filesystem::remove_all(dir); }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
};
