#version 330 core
// Depth only: the depth attachment is all this pass writes.
void main() {}
