// libsystemc's own main() calls sc_main(); rtusim's programs have their own main() and never
// reach it, but the shared library still needs the symbol to link.
#include <systemc>

int sc_main(int /*argc*/, char* /*argv*/[]) { return 1; }
