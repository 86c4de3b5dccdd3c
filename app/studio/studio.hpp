#pragma once
// `poreshell studio`: the browser front end's server (docs/studio.md). argv[0] is "studio".

int studio_main(int argc, char** argv);
