// Reads the example curve network through the installed meshfit and prints its feature points.
#include <meshfit/curve_network.h>
#include <meshfit/version.h>

#include <iostream>

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const meshfit::Curve_network net = meshfit::read_curve_network(argv[1]);
  std::cout << "meshfit " << MESHFIT_VERSION_STRING << ": " << net.feature_points().size()
            << " feature points\n";
  return net.feature_points().size() == 10 ? 0 : 1;
}
