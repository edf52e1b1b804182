#pragma once
// One error type for every bad input: the message always names the file and the problem.
#include <stdexcept>
#include <string>

namespace dmgplace::formats {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
  // "FILE: ELEMENT: REASON" (element may be empty).
  Error(const std::string& file, const std::string& element, const std::string& reason)
      : std::runtime_error(compose(file, element, reason)) {}

 private:
  static std::string compose(const std::string& file, const std::string& element, const std::string& reason) {
    std::string m = file.empty() ? std::string("<input>") : file;
    if (!element.empty()) m += ": " + element;
    return m + ": " + reason;
  }
};

}  // namespace dmgplace::formats

// The one error type of every layer (formats, runtime, tools, the CLI and Python's RuntimeError
// text): thrown and caught as dmgplace::Error.
namespace dmgplace {
using formats::Error;
}  // namespace dmgplace
