// Precompiled header of the meshfit library and tool: the heavy, stable headers.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>
#include <map>
#include <string>
#include <vector>
