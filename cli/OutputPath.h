#pragma once
// Output paths are checked before any work: a render or import that cannot write its result
// fails at once, not after minutes of work.
#include <string>

#include "vastray/core/Result.h"

namespace vastray::cli {

// The folder exists and is writable, and the file, if it exists, is a writable regular file.
// `flag` names the option in the message ("-o /ro/x.png: folder '/ro' is not writable (...)").
Status checkWritableOutput(const std::string& flag, const std::string& path);

}  // namespace vastray::cli
