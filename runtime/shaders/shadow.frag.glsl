void main() {} // depth only
