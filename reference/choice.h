// An option's choices, declared once beside the enum they select: each value with its spelling and what it selects.
// parse_choice reads a spelling (refusing an unknown one, or a renamed one with its new name), choice_name writes it,
// choices_help lists the choices for help texts. The algorithm options' table (bench/algo_options.h) is built on them.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "reference/error.h"

namespace uvr {

template <class E>
struct Choice {
    E value;
    std::string_view name;  // the spelling on the command line and in Python
    std::string_view help;  // what it selects
};

// A spelling that was renamed: refused with a message naming the new one.
struct RenamedChoice {
    std::string_view old_name;
    std::string_view new_name;
};

template <class E, std::size_t N>
using Choices = std::array<Choice<E>, N>;

// "a, b or c"
template <class E, std::size_t N>
std::string choice_names(const Choices<E, N>& choices)
{
    std::string s;
    for (std::size_t i = 0; i < N; ++i)
        s += std::string(i == 0 ? "" : i + 1 == N ? " or " : ", ") + std::string(choices[i].name);
    return s;
}

// The value `text` spells; InputError naming `option` otherwise.
template <class E, std::size_t N>
E parse_choice(std::string_view option, const Choices<E, N>& choices, const std::string& text,
               std::span<const RenamedChoice> renamed = {})
{
    for (const Choice<E>& c : choices)
        if (text == c.name) return c.value;
    for (const RenamedChoice& r : renamed)
        if (text == r.old_name)
            throw InputError("", std::string(option) + " " + text + " is now spelled " + std::string(option) + " " +
                                     std::string(r.new_name));
    throw InputError("", std::string(option) + " must be " + choice_names(choices) + ", not '" + text + "'");
}

template <class E, std::size_t N>
std::string_view choice_name(const Choices<E, N>& choices, E value)
{
    for (const Choice<E>& c : choices)
        if (c.value == value) return c.name;
    return "?";
}

// "a (what a selects) | b (what b selects)"
template <class E, std::size_t N>
std::string choices_help(const Choices<E, N>& choices)
{
    std::string s;
    for (const Choice<E>& c : choices)
        s += (s.empty() ? "" : " | ") + std::string(c.name) + (c.help.empty() ? "" : " (" + std::string(c.help) + ")");
    return s;
}

}  // namespace uvr
