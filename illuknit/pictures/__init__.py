"""Picture input: decoding picture files, quantising them to yarns, sizing pairs, drawn inputs."""
