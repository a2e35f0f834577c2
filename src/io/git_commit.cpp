// The commit the build comes from (io::git_commit), alone in its file: the header it reads is
// rewritten at each commit (cmake/git_commit.cmake), and only this small object recompiles.
#include <string>

#include "git_commit.hpp"  // VIADUCT_GIT_COMMIT, written at build time
#include "viaduct/io/results.hpp"

namespace viaduct::io {

std::string git_commit() { return VIADUCT_GIT_COMMIT; }

}  // namespace viaduct::io
