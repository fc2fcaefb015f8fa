// Errors a user can act on.
//
// Every failure caused by input (a file, an option, a transfer function) is an InputError whose message names the
// file and, for text formats, the line, followed by what is wrong: "post.vtk:12: expected 2288 points, file ends
// after 1000". The `uvr` program prints what() on stderr and exits non-zero; nothing below it ever aborts.
#pragma once

#include <stdexcept>
#include <string>

namespace uvr {

class InputError : public std::runtime_error {
public:
    // `file` may be empty for errors that concern no file (a command-line option).
    InputError(const std::string& file, const std::string& what);
    // `line` is 1-based; 0 means "no line" and is omitted from the message.
    InputError(const std::string& file, long line, const std::string& what);

    const std::string& file() const { return file_; }
    long line() const { return line_; }

private:
    std::string file_;
    long line_ = 0;
};

}  // namespace uvr
