#pragma once
/// @file gl.h
/// @brief The GL 4.5 core API (glad, generated at configure time) for code that issues GL calls.
#include <glad/gl.h>
