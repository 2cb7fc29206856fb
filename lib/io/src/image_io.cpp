// implemented by the I/O work in progress
