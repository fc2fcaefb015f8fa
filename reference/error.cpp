#include "reference/error.h"

namespace uvr {

namespace {
std::string compose(const std::string& file, long line, const std::string& what)
{
    std::string msg = file;
    if (!file.empty() && line > 0) msg += ":" + std::to_string(line);
    if (!msg.empty()) msg += ": ";
    return msg + what;
}
}  // namespace

InputError::InputError(const std::string& file, const std::string& what)
    : std::runtime_error(compose(file, 0, what)), file_(file)
{
}

InputError::InputError(const std::string& file, long line, const std::string& what)
    : std::runtime_error(compose(file, line, what)), file_(file), line_(line)
{
}

}  // namespace uvr
