// intermix-lab: measures the methods (eval against the reference, bench against VTK, z-fighting,
// intersection bands, CSG statistics). Users' commands are intermix's.
#include "lab_commands.hpp"

int main(int argc, char** argv) {
  using namespace imx::cli;
  static constexpr Subcommand kSubcommands[] = {
      {"eval", "every method on every scene against the reference: HTML report, JSON, tables",
       add_eval},
      {"bench", "time methods on a scene: median/min/max ms per frame (--vtk: and VTK's)",
       add_bench},
      {"zfight", "z-fighting metric of methods where coplanar surfaces coincide", add_zfight},
      {"band", "PSNR in the band around two objects' intersection curves", add_band},
      {"csg", "a CSG scene's primitives, products, clipping states and intervals per ray", add_csg},
  };
  return run_program("intermix-lab", "intermix-lab: measures intermix's methods", kSubcommands,
                     argc, argv);
}
