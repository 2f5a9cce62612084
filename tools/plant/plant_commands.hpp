#pragma once
// `dynweigh plant --can <transport> --scene NAME [--seed N] [--realtime] [--replay FILE]`.
int run_plant_command(int argc, char** argv);
