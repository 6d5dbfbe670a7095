// Bytes a container holds on the heap, for the solver's memory estimate (memory.cpp): a
// vector's size, not its capacity (a vector grown by doubling has not touched its spare
// half, which the machine does not give it until it does), and for a vector of vectors each
// inner one's too.
#pragma once
#include <cstddef>
#include <vector>

namespace radiosity {

template <class T>
double held_bytes(const std::vector<T>& v) {
    return double(v.size()) * double(sizeof(T));
}

template <class T>
double held_bytes(const std::vector<std::vector<T>>& v) {
    double b = double(v.size()) * double(sizeof(std::vector<T>));
    for (const std::vector<T>& inner : v) b += held_bytes(inner);
    return b;
}

}  // namespace radiosity
