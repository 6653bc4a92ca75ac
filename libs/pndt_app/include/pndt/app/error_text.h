// The message of an exception as one clean line of text for a user: MRPT's exceptions carry a
// "==== MRPT exception ====" banner, source locations, a call stack and the exceptions they
// wrap ("Original exception:"), which a user of an app should not have to read through.
#pragma once

#include <sstream>
#include <string>

namespace pndt::app
{
inline std::string plainErrorText(std::string what)
{
    constexpr const char* kInner = "Original exception:";
    if (const auto p = what.rfind(kInner); p != std::string::npos) what.erase(0, p + std::string(kInner).size());
    std::istringstream in(what);
    std::string line, text;
    while (std::getline(in, line))
    {
        if (line.rfind("Call stack", 0) == 0) break;
        if (line.rfind("==== MRPT exception", 0) == 0 || line.rfind("Location:", 0) == 0) continue;
        if (line.rfind("Message:", 0) == 0) line.erase(0, 8);
        const auto first = line.find_first_not_of(" \t");
        if (first == std::string::npos) continue;
        text += (text.empty() ? "" : "\n") + line.substr(first);
    }
    while (!text.empty() && (text.back() == ' ' || text.back() == '\n')) text.pop_back();
    return text;
}
}  // namespace pndt::app
